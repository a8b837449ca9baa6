// Every option of `radiosity solve`, declared once: its name, its help, the field of the request
// it sets and its check, how the settings echo shows it (the log's options, the result's
// `options` attribute), whether it is part of a checkpoint's identity, and the result's typed
// attribute and solve's --json key that record it. The command line (and with it --help, the man
// page, the completion and the job file's keys: jobs/solve_options.cpp) is made from this table,
// and so are describeSettings and runIdentity (run/checkpointing.h), recordOptions (the result's
// attributes) and recordedOptions (--json). Adding an option is an entry here, a field in
// SolveRequest and the code that uses it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "io/store/result.h"
#include "run/run_plan.h"
#include "run/solve_request.h"

namespace radiosity::run {

/// How an option's value is read and checked.
enum class OptionKind {
  kScene,       ///< the positional SCENE (in a job file, `scene = "..."`)
  kText,        ///< any text (a file name)
  kLengthUnit,  ///< a short unit name (m, mm, ft)
  kWhole,       ///< a whole number in [low, high]
  kSeed,        ///< a whole number in [0, 2^64 − 1], written in decimal
  kNumber,      ///< a finite number in [low, high] ((low, high] with openLow)
  kDuration,    ///< seconds, as batch users write them (run/duration.h)
  kRounds,      ///< "auto" (-1) or a whole number in [low, high]
  kFlag,        ///< on when given
  kQuiet,       ///< -q, as every command has it
  kChoice,      ///< one of `choices`, handed to `choose`
};

/// Where an option's value goes (every kind but kChoice).
using RequestField =
    std::variant<std::monostate, std::string SolveRequest::*, int64_t SolveRequest::*,
                 uint64_t SolveRequest::*, int SolveRequest::*, double SolveRequest::*,
                 bool SolveRequest::*>;

/// What the echo, the identity and the record see: the request, what the run chose, and the
/// area bound; for the record at the end, what the run found out too.
struct RunShown {
  const SolveRequest& request;
  const RunPlan& plan;
  double maxArea = 0;
  /// The scene's length unit as the run took it (--length-unit's, else the scene's; metres for a
  /// thermal run that states none); "": not known.
  std::string lengthUnit{};
  std::string solverUsed{};  ///< the solver that solved (solve::Report::solver); "": none yet
};
using ShownValue = std::function<std::string(const RunShown&)>;

/// A value the result records: text, a whole number, a seed (all 64 bits) or a flag.
using RecordedValue = std::variant<std::string, int64_t, uint64_t, bool>;

/// How the result records an option: the root attribute's name, which is also solve's --json
/// key (io/store/result_format.h), how the run's value is put into the attributes, and the
/// value --json shows, read back from them.
struct ResultRecord {
  const char* key = nullptr;  ///< none: the result has only the options line's echo
  std::function<void(const RunShown&, ResultAttributes&)> record{};
  std::function<RecordedValue(const ResultAttributes&)> shown{};
};

struct RequestOption {
  std::string name{};  ///< as the command line takes it: "--seed", "-o,--output", "SCENE"
  std::string help{};
  OptionKind kind = OptionKind::kText;
  RequestField field{};
  double low = 0, high = 0;  ///< kWhole, kNumber, kRounds
  bool openLow = false;      ///< kNumber: above low
  std::string hint{};        ///< kNumber: what a refusal adds
  /// --help's default, where not the field's own value ("": none shown).
  std::optional<std::string> defaultShown{};
  std::vector<std::string> choices{};                               ///< kChoice
  std::function<void(SolveRequest&, const std::string&)> choose{};  ///< kChoice
  std::vector<std::string> needs{}, excludes{};                     ///< other options' names
  /// The settings echo's value ("key = value"); empty: the line is left out.
  ShownValue echo{};
  /// The value in a checkpoint's identity (a restart must match it); none: not part of it.
  ShownValue identity{};
  /// The result's typed attribute and --json key that record the option; none: not recorded.
  ResultRecord result{};

  /// The name the echo, the identity and a job file give it: "seed", "output", "scene".
  std::string key() const;
};

/// The options in the order --help lists them: the scene and its mesh, the form factors, the
/// solve and the result, then how the run goes.
const std::vector<RequestOption>& requestOptions();

/// Puts every option the result records (each entry's `result`) into `attributes`.
void recordOptions(const RunShown& shown, ResultAttributes& attributes);

/// The options the result records, as solve's --json shows them: (key, value) in the table's
/// order.
std::vector<std::pair<std::string, RecordedValue>> recordedOptions(
    const ResultAttributes& attributes);

}  // namespace radiosity::run
