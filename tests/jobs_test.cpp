// Unit tests of the program's parts (the radiosity_jobs library) without running a command: the
// command line: its options, help and names. Runs on one rank (Console needs MPI). Job files,
// settings and outputs are tested in jobs_files_test.cpp, the table of solve's options in
// request_options_test.cpp, the run's control (checkpoint identity, safe points, durations) in
// run_control_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "jobs/command_line.h"
#include "jobs/job_file.h"
#include "jobs_fixture.h"
#include "mpi_environment.h"
#include "run/checkpointing.h"
#include "run/derived_settings.h"
#include "run/duration.h"
#include "run/node_memory.h"
#include "run/output_paths.h"
#include "run/safe_points.h"
#include "run/stage_reports.h"

namespace radiosity::jobs {
namespace {

// --- The command line -------------------------------------------------------------------------

TEST(CommandLine, SolveDefaults) {
  const CommandLine parsed = parse({"solve", "builtin:cornell"});
  EXPECT_EQ(parsed.command, "solve");
  EXPECT_EQ(parsed.solve.scene, "builtin:cornell");
  EXPECT_EQ(parsed.solve.raysPerPatch, 1024);
  EXPECT_FALSE(parsed.solve.estimator.has_value());  // "auto": chosen for the scene
  EXPECT_EQ(parsed.solve.output, "");                // the pipeline names it after the scene
  EXPECT_EQ(parsed.solve.balance, run::BalanceMode::kAuto);  // by cost from 4 ranks up
}

TEST(CommandLine, OptionsAreRead) {
  const CommandLine parsed =
      parse({"solve", "scene.obj", "--rays", "64", "--seed", "18446744073709551615", "--estimator",
             "mis", "-o", "x.h5", "--rtol", "1e-6", "--reciprocity"});
  EXPECT_EQ(parsed.solve.raysPerPatch, 64);
  EXPECT_EQ(parsed.solve.seed, 18446744073709551615u);
  EXPECT_EQ(parsed.solve.estimator, formfactor::Estimator::kEmitterMis);
  EXPECT_EQ(parsed.solve.output, "x.h5");
  EXPECT_DOUBLE_EQ(parsed.solve.rtol, 1e-6);
  EXPECT_TRUE(parsed.solve.reciprocity);
  EXPECT_EQ(parse({"solve", "scene.obj", "--balance", "count"}).solve.balance,
            run::BalanceMode::kCount);
  EXPECT_EQ(parse({"solve", "scene.obj", "--balance", "cost"}).solve.balance,
            run::BalanceMode::kCost);
}

TEST(CommandLine, NonFiniteAndOutOfRangeValuesAreUsageErrors) {
  for (const std::vector<std::string>& option :
       std::vector<std::vector<std::string>>{{"--rtol", "nan"},
                                             {"--rtol", "inf"},
                                             {"--rtol", "0"},
                                             {"--rtol", "2"},
                                             {"--max-area", "nan"},
                                             {"--max-area", "-1"},
                                             {"--rays", "0"},
                                             {"--seed", "-1"},
                                             {"--seed", "18446744073709551616"},
                                             {"--estimator", "best"},
                                             {"--balance", "even"},
                                             {"--threads", "0"},
                                             {"--refine-rounds", "-1"},
                                             {"--refine-rounds", "65"},
                                             {"--refine-rounds", "nan"},
                                             {"--refine-rounds", "2.5"},
                                             {"--refine-rounds", "always"},
                                             {"--max-patches", "0"},
                                             {"--max-patches", "1e99"}}) {
    std::vector<std::string> arguments{"solve", "builtin:cornell"};
    arguments.insert(arguments.end(), option.begin(), option.end());
    const Error e = thrownBy([&] { parse(arguments); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << option[0] << " " << option[1];
    EXPECT_NE(std::string(e.what()).find("--help"), std::string::npos) << e.what();
  }
}

// --refine-rounds: auto (the default, -1) or a count, as the help shows them.
TEST(CommandLine, RefineRoundsTakesAutoOrACount) {
  EXPECT_EQ(parse({"solve", "builtin:cornell"}).solve.refineRounds, -1);
  EXPECT_EQ(parse({"solve", "builtin:cornell", "--refine-rounds", "auto"}).solve.refineRounds, -1);
  EXPECT_EQ(parse({"solve", "builtin:cornell", "--refine-rounds", "0"}).solve.refineRounds, 0);
  EXPECT_EQ(parse({"solve", "builtin:cornell", "--refine-rounds", "0x2"}).solve.refineRounds, 2);
  EXPECT_EQ(parse({"solve", "builtin:cornell", "--max-patches", "5000"}).solve.maxPatches, 5000);
}

TEST(CommandLine, PatchesExcludesMaxArea) {
  const Error e = thrownBy([] {
    parse({"solve", "builtin:cornell", "--patches", "100", "--max-area", "1"});
  });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
}

// `render`'s output is named by its extension; the false-colour map, its scale and the exposure
// each go with one kind of output, and are refused with another before any work.
TEST(CommandLine, RenderOutputsAndTheirOptions) {
  const RenderSettings picture = parse({"render", "r.h5", "-o", "r.png"}).render;
  EXPECT_EQ(picture.falseColour, render::FalseColour::kNone);
  EXPECT_EQ(picture.scale, render::Scale::kAuto);
  const RenderSettings map =
      parse({"render", "r.h5", "-o", "m.PNG", "--false-colour", "irradiance", "--scale", "log"})
          .render;
  EXPECT_EQ(map.falseColour, render::FalseColour::kIrradiance);
  EXPECT_EQ(map.scale, render::Scale::kLog);
  EXPECT_EQ(parse({"render", "r.h5", "-o", "hdr.pfm"}).render.output, "hdr.pfm");
  struct Refused {
    std::vector<std::string> options;
    std::string says;
  };
  for (const Refused& refused : std::vector<Refused>{
           {{"-o", "r.tif"}, ".pfm"},
           {{"-o", "r"}, ".png"},
           {{"-o", "r.pfm", "--false-colour", "radiosity"}, "--false-colour"},
           {{"-o", "r.png", "--scale", "log"}, "--scale"},
           {{"-o", "r.pfm", "--exposure", "1"}, "--exposure"},
           {{"-o", "r.png", "--false-colour", "radiosity", "--exposure", "0"}, "--exposure"},
           {{"-o", "r.png", "--false-colour", "luminance"}, "--false-colour"},
           {{"-o", "r.png", "--false-colour", "radiosity", "--scale", "nan"}, "--scale"}}) {
    std::vector<std::string> arguments{"render", "r.h5"};
    arguments.insert(arguments.end(), refused.options.begin(), refused.options.end());
    const Error e = thrownBy([&] { parse(arguments); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << refused.options[1];
    EXPECT_NE(std::string(e.what()).find(refused.says), std::string::npos) << e.what();
  }
}

TEST(CommandLine, UnknownCommandIsNamed) {
  const Error e = thrownBy([] { parse({"solv", "builtin:cornell"}); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("unknown command 'solv'"), std::string::npos) << e.what();
}

TEST(CommandLine, NoCommandIsNamed) {
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{}, {"-q"}, {"--no-such-option", "x"}}) {
    const Error e = thrownBy([&] { parse(arguments); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage);
    EXPECT_NE(std::string(e.what()).find("no command given: the commands are solve, render, "),
              std::string::npos)
        << e.what();
  }
  // The list is the commands registered, all of them.
  const Error e = thrownBy([] { parse({"frobnicate"}); });
  for (const std::string command : {"solve", "render", "info", "xdmf", "scene", "study", "verify"})
    EXPECT_NE(std::string(e.what()).find(command), std::string::npos)
        << command << ": " << e.what();
}

TEST(CommandLine, HelpRunsNothing) { EXPECT_EQ(parse({"solve", "--help"}).command, ""); }

// A command's --help text, and in it the entry of one option: its line and the description
// lines under it.
std::string helpOf(const std::string& command) {
  ::testing::internal::CaptureStdout();
  parse({command, "--help"});
  return ::testing::internal::GetCapturedStdout();
}
std::string entryOf(const std::string& help, const std::string& option) {
  std::istringstream lines(help);
  std::string line, entry;
  while (std::getline(lines, line)) {
    const bool optionLine = line.rfind("  -", 0) == 0;
    if (optionLine && !entry.empty()) break;
    bool named = false;  // among the line's names, `-o,--output`
    std::istringstream names(optionLine ? line.substr(2, line.find(' ', 2) - 2) : "");
    for (std::string name; std::getline(names, name, ',');) named |= name == option;
    if (named)
      entry = line;
    else if (!entry.empty())
      entry.append("\n").append(line);
  }
  // One line, its runs of spaces one space: --help wraps descriptions to the terminal.
  std::string joined;
  for (char c : entry) {
    const bool space = c == ' ' || c == '\n';
    if (space && (joined.empty() || joined.back() == ' ')) continue;
    joined += space ? ' ' : c;
  }
  return joined;
}

// --help shows every option's default: after its type (`--rays INT:...=1024`) or, where it is
// worked out for the scene or the camera, in the description, never as the 0 or [] standing
// for it.
TEST(CommandLine, HelpShowsEveryDefault) {
  struct Shown {
    std::string command, option, text;
  };
  for (const Shown& shown : std::vector<Shown>{
           {"solve", "--rays", "=1024"},
           {"solve", "--seed", "=1"},
           {"solve", "--estimator", "=auto"},
           {"solve", "--threads", "=1"},
           {"solve", "--drop-threshold", "=0"},
           {"solve", "--checkpoint-every", "=600"},
           {"solve", "--output", "(default: the scene's name with .h5"},
           {"solve", "--max-area", "(default: total area / 4000)"},
           {"solve", "--solver", "(default: chosen for the scene"},
           {"solve", "--rtol", "(default: where the solver's error bound"},
           {"render", "--width", "=512"},
           {"render", "--height", "=512"},
           {"render", "--fov", "=40"},
           {"render", "--exposure", "=0"},
           {"render", "--up", "=0,1,0"},
           {"render", "--eye", "(default: looking along +z"},
           {"render", "--look-at", "(default: the centre"},
           {"render", "--scale", "=auto"},
           {"study", "--rays", "=16,32,64,128,256,512,1024"},
           {"study", "--estimator", "=hemisphere,mis"},
           {"study", "--rtol", "=1e-10"},
           {"study", "--solver", "=gmres"},
           {"study", "--max-area", "(default: the solve's"},
           {"study", "--reference", "(default: the scene's exact answer"},
           {"verify", "--patches", "=200"},
           {"verify", "--paths", "=16384"},
           {"verify", "--tol", "=0.05"},
           {"verify", "--seed", "=1"},
           {"xdmf", "--output", "(default: RESULT with .xmf)"},
       }) {
    const std::string entry = entryOf(helpOf(shown.command), shown.option);
    EXPECT_NE(entry.find(shown.text), std::string::npos)
        << shown.command << " " << shown.option << ": " << entry;
  }
  // Worked out, or off unless given: no value shown that would mislead.
  for (const Shown& none : std::vector<Shown>{{"solve", "--max-area", ""},
                                              {"solve", "--patches", ""},
                                              {"solve", "--rtol", ""},
                                              {"solve", "--target-error", ""},
                                              {"render", "--eye", ""},
                                              {"render", "--look-at", ""},
                                              {"study", "--max-area", ""}}) {
    const std::string entry = entryOf(helpOf(none.command), none.option);
    const std::string firstLine = entry.substr(0, entry.find('\n'));
    EXPECT_FALSE(firstLine.empty()) << none.command << " " << none.option;
    EXPECT_EQ(firstLine.find("]="), std::string::npos) << none.command << ": " << firstLine;
  }
}

TEST(CommandLine, NamesAndEnumsRoundTrip) {
  for (const std::string& name : solve::solverNames())
    EXPECT_EQ(solve::solverName(solve::solverNamed(name)), name);
  EXPECT_THROW(solve::solverNamed("auto"), std::invalid_argument);
  for (const std::string name : {"hemisphere", "mis"})
    EXPECT_EQ(formfactor::estimatorName(formfactor::estimatorNamed(name)), name);
  EXPECT_THROW(formfactor::estimatorNamed("auto"), std::invalid_argument);
  EXPECT_EQ(parse({"study", "builtin:box", "-o", "s.csv", "--solver", "cg"}).study.solver,
            solve::Solver::kCg);
}

TEST(CommandLine, StudyListsAreSplit) {
  const CommandLine parsed =
      parse({"study", "builtin:box", "-o", "s.csv", "--rays", "16,64", "--estimator", "mis"});
  EXPECT_EQ(parsed.command, "study");
  EXPECT_EQ(parsed.study.rays, (std::vector<int64_t>{16, 64}));
  EXPECT_EQ(parsed.study.estimators,
            (std::vector<formfactor::Estimator>{formfactor::Estimator::kEmitterMis}));
}

// Every table of names reads both ways, each name once; an unknown name is none.
template <class Value, size_t N>
void expectRoundTrip(const NamedValue<Value> (&table)[N], const char* what) {
  std::set<std::string> names;
  std::vector<std::string> inOrder;
  for (const NamedValue<Value>& row : table) {
    EXPECT_TRUE(names.insert(row.name).second) << what << ": " << row.name << " twice";
    EXPECT_STREQ(nameIn(table, row.value), row.name) << what;
    EXPECT_EQ(valueNamed(table, row.name), std::optional<Value>(row.value)) << what;
    inOrder.emplace_back(row.name);
  }
  EXPECT_EQ(namesIn(table), inOrder) << what;
  EXPECT_FALSE(valueNamed(table, "no-such-name").has_value()) << what;
  EXPECT_FALSE(valueNamed(table, "").has_value()) << what;
}

TEST(EnumNames, EveryTableReadsBothWays) {
  expectRoundTrip(formfactor::kEstimatorNames, "estimators");
  expectRoundTrip(solve::kSolverNames, "solvers");
  expectRoundTrip(run::kBalanceModes, "balance modes");
  expectRoundTrip(run::kContactsModes, "--contacts");
  expectRoundTrip(run::kExactRowsModes, "--exact-rows");
  expectRoundTrip(render::kFalseColourNames, "--false-colour");
  expectRoundTrip(render::kScaleNames, "--scale");
  EXPECT_EQ(solve::solverNames(), namesIn(solve::kSolverNames));
  EXPECT_STREQ(nameIn(run::kBalanceModes, static_cast<run::BalanceMode>(99), "none"), "none");
}

TEST(EnumNames, ChoicesAreDescribedWithTheirHelp) {
  constexpr NamedValue<int> table[] = {{1, "one", "the first"}, {2, "two"}, {3, "three", "last"}};
  EXPECT_EQ(choicesDescribed(table), "one (the first), two or three (last)");
  EXPECT_EQ(choicesDescribed(table, " | ", " | "), "one (the first) | two | three (last)");
  constexpr NamedValue<int> single[] = {{1, "one"}};
  EXPECT_EQ(choicesDescribed(single), "one");
}

// The command line takes its choices from the tables: every row's name is accepted and turned
// into its value, and listed in --help, without an edit of the command line.
TEST(CommandLine, EveryTableNameIsAChoice) {
  for (const auto& [estimator, name, help] : formfactor::kEstimatorNames) {
    EXPECT_EQ(parse({"solve", "s.obj", "--estimator", name}).solve.estimator, estimator);
    EXPECT_EQ(parse({"study", "s.obj", "-o", "s.csv", "--estimator", name}).study.estimators,
              std::vector<formfactor::Estimator>{estimator});
    EXPECT_NE(entryOf(helpOf("solve"), "--estimator").find(std::string(name) + " ("),
              std::string::npos)
        << name;
  }
  for (const auto& [solver, name, help] : solve::kSolverNames) {
    EXPECT_EQ(parse({"solve", "s.obj", "--solver", name}).solve.solver, solver);
    EXPECT_EQ(parse({"study", "s.obj", "-o", "s.csv", "--solver", name}).study.solver, solver);
    EXPECT_NE(entryOf(helpOf("solve"), "--solver").find(name), std::string::npos) << name;
  }
  for (const auto& [mode, name, help] : run::kBalanceModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--balance", name}).solve.balance, mode);
  for (const auto& [cut, name, help] : run::kContactsModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--contacts", name}).solve.cutContacts, cut);
  for (const auto& [allowed, name, help] : run::kExactRowsModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--exact-rows", name}).solve.exactRowsAllowed, allowed);
  for (const auto& [shown, name, help] : render::kFalseColourNames) {
    EXPECT_EQ(parse({"render", "r.h5", "-o", "r.png", "--false-colour", name}).render.falseColour,
              shown);
    EXPECT_NE(entryOf(helpOf("render"), "--false-colour").find(std::string(name) + " ("),
              std::string::npos)
        << name;
  }
  for (const auto& [scale, name, help] : render::kScaleNames)
    EXPECT_EQ(
        parse({"render", "r.h5", "-o", "r.png", "--false-colour", "radiosity", "--scale", name})
            .render.scale,
        scale);
  EXPECT_FALSE(parse({"solve", "s.obj", "--estimator", "auto"}).solve.estimator.has_value());
  for (const std::string option : {"--contacts", "--exact-rows", "--solver", "--balance"}) {
    const Error e = thrownBy([&] { parse({"solve", "s.obj", option, "none-such"}); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << option;
  }
}

// --stop-after is a duration and needs --checkpoint (run/duration.h reads it).
TEST(CommandLine, StopAfterNeedsACheckpointAndADuration) {
  EXPECT_EQ(parse({"solve", "builtin:box", "--checkpoint", "c.h5", "--stop-after", "3h50m"})
                .solve.stopAfter,
            13800);
  EXPECT_EQ(parse({"solve", "builtin:box"}).solve.stopAfter, 0);
  EXPECT_EQ(thrownBy([] {
              parse({"solve", "builtin:box", "--stop-after", "1h"});
            }).exitCode(),
            exit_code::kUsage);
  EXPECT_EQ(thrownBy([] {
              parse({"solve", "builtin:box", "--checkpoint", "c.h5", "--stop-after", "1h30"});
            }).exitCode(),
            exit_code::kUsage);
}

}  // namespace
}  // namespace radiosity::jobs
