// Every option of `radiosity solve`, declared once: its name, its help, the field of the request
// it sets and its check, how the settings echo shows it (the log's options, the result's
// `options` attribute) and whether it is part of a checkpoint's identity. The command line (and
// with it --help, the man page, the completion and the job file's keys: jobs/solve_options.cpp)
// is made from this table, and so are describeSettings and runIdentity (run/checkpointing.h).
// Adding an option is an entry here, a field in SolveRequest and the code that uses it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

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

/// What the echo and the identity see: the request, what the run chose, and the area bound.
struct RunShown {
  const SolveRequest& request;
  const RunPlan& plan;
  double maxArea = 0;
};
using ShownValue = std::function<std::string(const RunShown&)>;

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

  /// The name the echo, the identity and a job file give it: "seed", "output", "scene".
  std::string key() const;
};

/// The options in the order --help lists them: the scene and its mesh, the form factors, the
/// solve and the result, then how the run goes.
const std::vector<RequestOption>& requestOptions();

}  // namespace radiosity::run
