// Each command's options, declared once with their checks and bound to the command's settings
// (filled in as CLI11 parses), for jobs/command_line.cpp. Each adds its subcommand to `app`
// and returns it. Choices and their help come from the value tables (core/enum_names.h), so a
// new estimator or solver is a row there, not an edit here.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "jobs/commands.h"

namespace radiosity::jobs {

CLI::App* addSolveCommand(CLI::App& app, SolveSettings& settings);    ///< jobs/solve_options.cpp
CLI::App* addRenderCommand(CLI::App& app, RenderSettings& settings);  ///< jobs/command_options.cpp
CLI::App* addInfoCommand(CLI::App& app, std::string& resultPath);
CLI::App* addXdmfCommand(CLI::App& app, XdmfSettings& settings);
CLI::App* addSceneCommand(CLI::App& app, SceneSettings& settings);
CLI::App* addStudyCommand(CLI::App& app, StudySettings& settings);
CLI::App* addVerifyCommand(CLI::App& app, VerifySettings& settings);

}  // namespace radiosity::jobs
