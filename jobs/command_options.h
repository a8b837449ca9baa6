// Each command's options, declared once with their checks and bound to the command's settings
// (filled in as CLI11 parses), for jobs/command_line.cpp. Choices and their help come from the
// value tables (core/enum_names.h), so a new estimator or solver is a row there, not an edit here.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "jobs/command_line.h"

namespace radiosity::jobs {

/// Adds a command and its options to `app`, bound to the command's settings in `parsed`.
using AddCommand = void (*)(CLI::App& app, CommandLine& parsed);

void addSolveCommand(CLI::App& app, CommandLine& parsed);   ///< jobs/solve_options.cpp
void addRenderCommand(CLI::App& app, CommandLine& parsed);  ///< jobs/command_options.cpp
void addInfoCommand(CLI::App& app, CommandLine& parsed);
void addXdmfCommand(CLI::App& app, CommandLine& parsed);
void addSceneCommand(CLI::App& app, CommandLine& parsed);
void addStudyCommand(CLI::App& app, CommandLine& parsed);
void addVerifyCommand(CLI::App& app, CommandLine& parsed);
void addExportCommand(CLI::App& app, CommandLine& parsed);

/// -q: warnings and errors only, no log (run/console.h), for every command.
void addQuietFlag(CLI::App& command, bool& quiet);
/// --json: a JSON summary on stdout (docs/json-summaries.md); the report joins the log.
void addJsonFlag(CLI::App& command, bool& json);

/// The commands, in the order --help and the usage errors list them.
inline constexpr AddCommand kCommands[] = {addSolveCommand,  addRenderCommand, addInfoCommand,
                                           addXdmfCommand,   addSceneCommand,  addStudyCommand,
                                           addVerifyCommand, addExportCommand};

}  // namespace radiosity::jobs
