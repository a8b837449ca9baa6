// The program's command line, parsed apart from running it (command_line.cpp), so that what it
// accepts and refuses can be tested without running a command.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "jobs/commands.h"
#include "run/console.h"

namespace CLI {
class App;
}

namespace radiosity::jobs {

/// The command chosen and the settings of each command (only the chosen one's are filled in).
struct CommandLine {
  std::string command;  ///< "solve", "render", ...; empty: --help or --version, already printed
  run::SolveRequest solve;
  RenderSettings render;
  std::string info;  ///< the result file `info` shows
  SceneSettings scene;
  XdmfSettings xdmf;
  StudySettings study;
  VerifySettings verify;
  ExportSettings exportTables;
  bool quiet = false;  ///< -q of a command without settings of its own for it: no log
  bool json =
      false;  ///< --json (solve, info, verify): a JSON summary on stdout, the rest on stderr
};

/// Declares every command and option of the program on `app`, bound to `parsed`, with --help
/// wrapped to `helpColumns` (also for the man page and the completion script, jobs/help_pages.cpp).
void declareCommandLine(CLI::App& app, CommandLine& parsed, std::size_t helpColumns);

/// Parses the program's own arguments (PETSc's were taken out before), `--config` job files
/// expanded. Throws Error(exit_code::kUsage) for a usage error (an unknown command or option, a
/// value out of range) and InputError (exit_code::kBadInput, "file:line: ...") for a bad job
/// file or a value of it refused. Prints the help or version text on rank 0 when asked.
CommandLine parseCommandLine(const std::vector<std::string>& arguments, const run::Console& console,
                             const std::vector<std::string>& petscWords = {});

}  // namespace radiosity::jobs
