// The command line of `radiosity solve`, made from its table of options (run/request_options.h):
// each entry becomes a CLI11 option bound to the request, with its check, in the table's order.
#include "core/enum_names.h"
#include "jobs/command_options.h"
#include "jobs/option_checks.h"
#include "run/request_options.h"

namespace radiosity::jobs {

namespace {

using run::OptionKind;
using run::RequestOption;
using run::SolveRequest;

// The value the option's field is parsed into, as CLI11 types it.
template <class T>
T& fieldOf(const RequestOption& option, SolveRequest& s) {
  return s.*std::get<T SolveRequest::*>(option.field);
}

CLI::Option* addWhole(CLI::App& solve, const RequestOption& option, SolveRequest& s) {
  const auto low = static_cast<int64_t>(option.low), high = static_cast<int64_t>(option.high);
  if (std::holds_alternative<int SolveRequest::*>(option.field))
    return solve.add_option(option.name, fieldOf<int>(option, s), option.help)
        ->check(CLI::Range(static_cast<int>(low), static_cast<int>(high)));
  return solve.add_option(option.name, fieldOf<int64_t>(option, s), option.help)
      ->check(CLI::Range(low, high));
}

// "auto" (-1) or a whole number in the option's range.
CLI::Option* addRounds(CLI::App& solve, const RequestOption& option, SolveRequest& s) {
  int& rounds = fieldOf<int>(option, s);
  return solve
      .add_option_function<std::string>(
          option.name,
          [&rounds](const std::string& value) {
            int given = -1;  // "auto"; otherwise as the check read it (0x2, 1_0 alike)
            if (value != "auto") CLI::detail::lexical_cast(value, given);
            rounds = given;
          },
          option.help)
      ->check(CLI::IsMember({"auto"}) |
              CLI::Range(static_cast<int>(option.low), static_cast<int>(option.high)));
}

CLI::Option* addRequestOption(CLI::App& solve, const RequestOption& option, SolveRequest& s) {
  switch (option.kind) {
    case OptionKind::kScene: {
      std::string& scene = fieldOf<std::string>(option, s);
      // A job file's `scene` key, not shown: SCENE is the one way --help gives (the command
      // line's SCENE wins, as every option of the command line wins over the job file's).
      solve
          .add_option_function<std::string>("--" + option.key(),
                                            [&scene](const std::string& given) {
                                              if (scene.empty()) scene = given;
                                            })
          ->group("");
      return solve.add_option(option.name, scene, option.help);
    }
    case OptionKind::kText:
      return solve.add_option(option.name, fieldOf<std::string>(option, s), option.help);
    case OptionKind::kLengthUnit:
      return solve.add_option(option.name, fieldOf<std::string>(option, s), option.help)
          ->check(lengthUnitName());
    case OptionKind::kWhole:
      return addWhole(solve, option, s);
    case OptionKind::kSeed:
      return solve.add_option(option.name, fieldOf<uint64_t>(option, s), option.help)
          ->check(seedValue());
    case OptionKind::kNumber:
      return addNumber(solve, option.name, fieldOf<double>(option, s), option.help,
                       finiteIn(option.low, option.high, option.openLow, option.hint));
    case OptionKind::kDuration:
      return addDuration(solve, option.name, fieldOf<double>(option, s), option.help);
    case OptionKind::kRounds:
      return addRounds(solve, option, s);
    case OptionKind::kFlag:
      return solve.add_flag(option.name, fieldOf<bool>(option, s), option.help);
    case OptionKind::kQuiet:
      addQuietFlag(solve, fieldOf<bool>(option, s));
      return nullptr;
    case OptionKind::kChoice:
      return addChoice(
          solve, option.name, option.choices,
          [&s, &option](const std::string& name) { option.choose(s, name); }, option.help);
  }
  return nullptr;
}

}  // namespace

void addSolveCommand(CLI::App& app, CommandLine& parsed) {
  CLI::App* solve = app.add_subcommand("solve", "solve a scene and write the result (HDF5)");
  // A job file's value comes first on the expanded command line; the user's later one wins.
  solve->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  for (const RequestOption& option : run::requestOptions()) {
    CLI::Option* added = addRequestOption(*solve, option, parsed.solve);
    if (added == nullptr) continue;
    if (option.defaultShown) added->default_str(*option.defaultShown);
    for (const std::string& other : option.needs) added->needs(other);
    for (const std::string& other : option.excludes) added->excludes(other);
  }
  addJsonFlag(*solve, parsed.json);
  solve->add_option("--config", "TOML job file holding any of these options: `rays = 4096`");
}

}  // namespace radiosity::jobs
