// Every option of the program is declared once, with its check (jobs/solve_options.cpp,
// jobs/command_options.cpp). CLI11 parses the command line; a --config job file (TOML,
// jobs/job_file.h: `rays = 4096`) is expanded into options first (jobs/job_file_expansion.h),
// and its unknown keys are refused. Names of estimators, solvers and modes are checked against
// their tables (core/enum_names.h) and turned into values once.
#include "jobs/command_line.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <set>
#include <sstream>

#include "core/error.h"
#include "jobs/command_options.h"
#include "jobs/help_format.h"
#include "jobs/job_file.h"
#include "jobs/job_file_expansion.h"
#include "jobs/json_summaries.h"
#include "run/version.h"

namespace radiosity::jobs {

namespace {

// An unknown or missing command is named, with the list of commands (as registered, so that a
// new one is listed), not reported as "a subcommand is required".
void checkCommandGiven(const CLI::App& app, const std::vector<std::string>& arguments) {
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(command->get_name());
  std::string commands;
  for (size_t i = 0; i < names.size(); ++i)
    commands += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  const std::string usage = ": the commands are " + commands + " (run with --help for usage)";
  auto isArgument = [&](const std::string& word) {
    return std::find(arguments.begin(), arguments.end(), word) != arguments.end();
  };
  const bool commandGiven = std::any_of(names.begin(), names.end(), isArgument);
  if (!arguments.empty() && !arguments[0].empty() && arguments[0][0] != '-' &&
      std::find(names.begin(), names.end(), arguments[0]) == names.end())
    throw Error(exit_code::kUsage, "unknown command '" + shown(arguments[0]) + "'" + usage);
  if (!commandGiven && !isArgument("-h") && !isArgument("--help") && !isArgument("--version"))
    throw Error(exit_code::kUsage, "no command given" + usage);
}

void printHelp(const CLI::App& app, const CLI::Error& call, const run::Console& console) {
  std::ostringstream text;
  app.exit(call, text, text);
  console.result(text.str());
}

// Parses `expanded` into the settings bound to `app`'s options. False: --help or --version was
// asked for, and its text is printed.
bool parseArguments(CLI::App& app, const ExpandedArguments& expanded, const run::Console& console) {
  std::vector<std::string> reversed(expanded.arguments.rbegin(), expanded.arguments.rend());
  try {
    app.parse(reversed);
    return true;
  } catch (const CLI::CallForHelp& e) {
    printHelp(app, e, console);
  } catch (const CLI::CallForAllHelp& e) {
    printHelp(app, e, console);
  } catch (const CLI::CallForVersion&) {
    console.result(run::versionText());
  } catch (const CLI::ParseError& e) {
    throwParseRefusal(e.what(), expanded.origin);
  }
  return false;
}

// Our options take two dashes; a word with one dash and a letter goes to PETSc (main.cpp), which
// would ignore `-rays 16` but for a warning at the end of the run: refused before any work, with
// the spelling meant. (PETSc's own -help and -version are PETSc's.)
void refuseOneDashSpellings(CLI::App& app, const std::vector<std::string>& petscWords) {
  std::set<std::string> ours;
  std::vector<CLI::App*> commands = app.get_subcommands([](CLI::App*) { return true; });
  commands.push_back(&app);
  for (CLI::App* command : commands)
    for (const CLI::Option* option : command->get_options())
      for (const std::string& name : option->get_lnames()) ours.insert(name);
  for (const std::string& word : petscWords) {
    if (word.size() < 3 || word[0] != '-' || word[1] == '-') continue;
    const std::string name = word.substr(1);
    if (name == "help" || name == "version" || ours.count(name) == 0) continue;
    throw Error(exit_code::kUsage, word + ": radiosity's options take two dashes: did you mean --" +
                                       name + "? (a word with one dash goes to PETSc)");
  }
}

int runCommand(const CommandLine& parsed, const run::Console& console) {
  if (parsed.command == "solve") return run::runSolve(parsed.solve, console);
  if (parsed.command == "render") return runRender(parsed.render, console);
  if (parsed.command == "info") return runInfo(parsed.info, console);
  if (parsed.command == "scene") return runScene(parsed.scene, console);
  if (parsed.command == "study") return runStudy(parsed.study, console);
  if (parsed.command == "verify") return runVerify(parsed.verify, console);
  if (parsed.command == "xdmf") return runXdmf(parsed.xdmf, console);
  if (parsed.command == "export") return runExport(parsed.exportTables, console);
  return exit_code::kOk;  // --help or --version, printed
}

}  // namespace

void declareCommandLine(CLI::App& app, CommandLine& parsed, std::size_t helpColumns) {
  app.description(
      "radiosity: diffuse global illumination on MPI ranks (PETSc options such as "
      "-ksp_type or -log_view go after the scene)");
  app.name("radiosity");
  app.require_subcommand(1);
  app.set_version_flag("--version", run::versionText());
  // --help shows each option's default after its type (`--rays INT=1024`). An option whose
  // default is worked out (for the scene, the camera) or which is off unless given shows none
  // there (default_str("")), rather than the 0 or [] that stands for it; its description says.
  app.option_defaults()->always_capture_default();
  // (before the commands: they copy it)
  app.formatter(std::make_shared<WrappedHelp>(helpColumns));
  for (const AddCommand add : kCommands) add(app, parsed);
}

CommandLine parseCommandLine(const std::vector<std::string>& arguments, const run::Console& console,
                             const std::vector<std::string>& petscWords) {
  CommandLine parsed;
  CLI::App app;
  declareCommandLine(app, parsed, helpWidth());
  refuseOneDashSpellings(app, petscWords);

  checkCommandGiven(app, arguments);
  // The job file holds solve's options.
  const ExpandedArguments expanded = expandJobFile(arguments, *app.get_subcommand("solve"));
  if (!parseArguments(app, expanded, console)) return parsed;

  parsed.solve.jobFile = expanded.origin.file;  // an input: never an output of the run
  for (const CLI::App* command : app.get_subcommands()) parsed.command = command->get_name();
  if (parsed.command == "solve" && parsed.solve.scene.empty())
    throw Error(exit_code::kUsage,
                "solve: no scene given: name a scene file or builtin:NAME (or `scene = \"...\"` "
                "in the --config job file; run with --help for usage)");
  // (CLI11 requires one subcommand; this is only for safety)
  if (parsed.command.empty())
    throw Error(exit_code::kUsage, "no command (run with --help for usage)");
  return parsed;
}

int runCommandLine(const std::vector<std::string>& arguments, const run::Console& console,
                   const std::vector<std::string>& petscWords) {
  const CommandLine parsed = parseCommandLine(arguments, console, petscWords);
  run::Console used =
      parsed.quiet || parsed.solve.quiet || parsed.study.quiet ? console.quietened() : console;
  if (parsed.json) used = used.forJson();
  if (parsed.solve.verbose) used = used.verbose();
  try {
    return runCommand(parsed, used);
  } catch (const Error& e) {
    // A script reading --json's stdout gets a document whatever happened.
    if (parsed.json) used.json(failureJson(parsed.command, e.exitCode(), e.what()));
    throw;
  }
}

}  // namespace radiosity::jobs
