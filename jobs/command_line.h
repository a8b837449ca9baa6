// The program's command line, parsed apart from running it (command_line.cpp), so that what it
// accepts and refuses can be tested without running a command.
#pragma once

#include <string>
#include <vector>

#include "jobs/commands.h"
#include "jobs/console.h"

namespace radiosity::jobs {

/// The command chosen and the settings of each command (only the chosen one's are filled in).
struct CommandLine {
  std::string command;  ///< "solve", "render", ...; empty: --help or --version, already printed
  SolveSettings solve;
  RenderSettings render;
  std::string info;  ///< the result file `info` shows
  SceneSettings scene;
  XdmfSettings xdmf;
  StudySettings study;
  VerifySettings verify;
  ExportSettings exportTables;
};

/// Parses the program's own arguments (PETSc's were taken out before), `--config` job files
/// expanded. Throws Error(exit_code::kUsage) for a usage error (an unknown command or option, a
/// value out of range) and InputError (exit_code::kBadInput, "file:line: ...") for a bad job
/// file or a value of it refused. Prints the help or version text on rank 0 when asked.
CommandLine parseCommandLine(const std::vector<std::string>& arguments, const Console& console,
                             const std::vector<std::string>& petscWords = {});

}  // namespace radiosity::jobs
