// Unit tests of the program's parts (the radiosity_jobs library) without running a command: the
// command line and its job files, the identity that ties a checkpoint to its run, the safe
// points where signals are acted on, and what the solve derives from its settings. Runs on one
// rank (Console and SafePoints need MPI).
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
#include "jobs/checkpointing.h"
#include "jobs/command_line.h"
#include "jobs/duration.h"
#include "jobs/job_file.h"
#include "jobs/node_memory.h"
#include "jobs/output_paths.h"
#include "jobs/safe_points.h"
#include "jobs/solve_settings.h"
#include "jobs/stage_reports.h"
#include "mpi_environment.h"
#include "test_scenes.h"

namespace radiosity::jobs {
namespace {

// A file in a fresh temporary folder, removed with the test.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("jobs_test_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// The Error `work` throws (failing the test if none), for its exit code and message.
Error thrownBy(const std::function<void()>& work) {
  try {
    work();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no radiosity::Error thrown";
  return Error(-1, "");
}

CommandLine parse(const std::vector<std::string>& arguments) {
  const Console console(MPI_COMM_WORLD);
  return parseCommandLine(arguments, console);
}

// --- The command line -------------------------------------------------------------------------

TEST(CommandLine, SolveDefaults) {
  const CommandLine parsed = parse({"solve", "builtin:cornell"});
  EXPECT_EQ(parsed.command, "solve");
  EXPECT_EQ(parsed.solve.scene, "builtin:cornell");
  EXPECT_EQ(parsed.solve.raysPerPatch, 1024);
  EXPECT_FALSE(parsed.solve.estimator.has_value());     // "auto": chosen for the scene
  EXPECT_EQ(parsed.solve.output, "");                   // the pipeline names it after the scene
  EXPECT_EQ(parsed.solve.balance, BalanceMode::kAuto);  // by cost from 4 ranks up
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
  EXPECT_EQ(parse({"solve", "scene.obj", "--balance", "count"}).solve.balance, BalanceMode::kCount);
  EXPECT_EQ(parse({"solve", "scene.obj", "--balance", "cost"}).solve.balance, BalanceMode::kCost);
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
  return entry;
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
  expectRoundTrip(kBalanceModes, "balance modes");
  expectRoundTrip(kContactsModes, "--contacts");
  expectRoundTrip(kExactRowsModes, "--exact-rows");
  EXPECT_EQ(solve::solverNames(), namesIn(solve::kSolverNames));
  EXPECT_STREQ(nameIn(kBalanceModes, static_cast<BalanceMode>(99), "none"), "none");
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
  for (const auto& [mode, name, help] : kBalanceModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--balance", name}).solve.balance, mode);
  for (const auto& [cut, name, help] : kContactsModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--contacts", name}).solve.cutContacts, cut);
  for (const auto& [allowed, name, help] : kExactRowsModes)
    EXPECT_EQ(parse({"solve", "s.obj", "--exact-rows", name}).solve.exactRowsAllowed, allowed);
  EXPECT_FALSE(parse({"solve", "s.obj", "--estimator", "auto"}).solve.estimator.has_value());
  for (const std::string option : {"--contacts", "--exact-rows", "--solver", "--balance"}) {
    const Error e = thrownBy([&] { parse({"solve", "s.obj", option, "none-such"}); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << option;
  }
}

// The options line names the modes that are not the default by their table names.
TEST(SolveSettings, OptionsLineNamesModes) {
  SolveSettings settings = parse({"solve", "s.obj", "--balance", "count", "--contacts", "off",
                                  "--exact-rows", "off", "--solver", "gauss-seidel"})
                               .solve;
  const std::string line = describeSettings(settings, 1, 2);
  for (const std::string expected :
       {"\nbalance = count\n", "\ncontacts = off\n", "\nexact-rows = off\n",
        "\nsolver = gauss-seidel\n", "\nestimator = auto\n"})
    EXPECT_NE(line.find(expected), std::string::npos) << expected << " in " << line;
  const std::string defaults = describeSettings(parse({"solve", "s.obj"}).solve, 1, 2);
  for (const std::string absent : {"balance", "contacts", "exact-rows"})
    EXPECT_EQ(defaults.find(absent), std::string::npos) << absent << " in " << defaults;
}

TEST(CommandLine, JobFileValuesAreUsedAndTheCommandLineWins) {
  const TempFile job("values.toml",
                     "# a job\n[solve]\nrays = 4096\nsolver = \"gmres\"\nquiet = true\n"
                     "seed = 7  # trailing comment\n");
  const CommandLine fromFile = parse({"solve", "builtin:cornell", "--config", job.path()});
  EXPECT_EQ(fromFile.solve.raysPerPatch, 4096);
  EXPECT_EQ(fromFile.solve.solver, solve::Solver::kGmres);
  EXPECT_TRUE(fromFile.solve.quiet);
  EXPECT_EQ(fromFile.solve.seed, 7u);
  const CommandLine overridden =
      parse({"solve", "builtin:cornell", "--config=" + job.path(), "--rays", "8"});
  EXPECT_EQ(overridden.solve.raysPerPatch, 8);
  EXPECT_EQ(overridden.solve.seed, 7u);
}

TEST(CommandLine, JobFileTomlValuesReachTheOptions) {
  const TempFile job("forms.toml",
                     "[solve]\nscene = 'builtin:cornell'\nrays = 4_096\nseed = 0x10\n"
                     "rtol = 1e-3\ncheckpoint-every = 0.30000000000000004\nquiet = true\n"
                     "reciprocity = false\n");
  const CommandLine parsed = parse({"solve", "--config", job.path()});
  EXPECT_EQ(parsed.solve.scene, "builtin:cornell");
  EXPECT_EQ(parsed.solve.raysPerPatch, 4096);
  EXPECT_EQ(parsed.solve.seed, 16u);
  EXPECT_EQ(parsed.solve.rtol, 1e-3);
  EXPECT_EQ(parsed.solve.checkpointEvery, 0.1 + 0.2);  // every digit kept
  EXPECT_TRUE(parsed.solve.quiet);
  EXPECT_FALSE(parsed.solve.reciprocity);
}

TEST(CommandLine, JobFileValueRefusedWithItsLine) {
  for (const std::string value : {"nan", "inf", "-inf", "\"abc\"", "2.5"}) {
    const TempFile job("refused.toml", "rays = 64\nrtol = " + value + "\n");
    const Error e = thrownBy([&] { parse({"solve", "builtin:cornell", "--config", job.path()}); });
    EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
    EXPECT_EQ(std::string(e.what()).rfind(job.path() + ":2: ", 0), 0u) << e.what();
  }
  const TempFile rays("rays.toml", "\nrays = 1.5\n");
  const Error e = thrownBy([&] { parse({"solve", "builtin:cornell", "--config", rays.path()}); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_EQ(std::string(e.what()).rfind(rays.path() + ":2: ", 0), 0u) << e.what();
}

TEST(CommandLine, JobFileUnknownKeyAndBadFlagRefused) {
  const TempFile unknown("unknown.toml", "rays = 64\n\nray = 64\n");
  Error e = thrownBy([&] { parse({"solve", "builtin:cornell", "--config", unknown.path()}); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_EQ(std::string(e.what()), unknown.path() + ":3: unknown key 'ray'");
  const TempFile flag("flag.toml", "quiet = \"yes\"\n");
  e = thrownBy([&] { parse({"solve", "builtin:cornell", "--config", flag.path()}); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find(":1: 'quiet' takes true or false"), std::string::npos);
}

// One job file per run: a second --config would silently replace the first (they are not
// layered), so it is refused; the one given is known to the run as an input.
TEST(CommandLine, SecondJobFileRefusedAndTheJobFileIsKnown) {
  const TempFile first("first.toml", "rays = 64\n"), second("second.toml", "rays = 128\n");
  const Error e = thrownBy([&] {
    parse({"solve", "builtin:cornell", "--config", first.path(), "--config=" + second.path()});
  });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("--config is given twice"), std::string::npos) << e.what();
  EXPECT_EQ(parse({"solve", "builtin:cornell", "--config", first.path()}).solve.jobFile,
            first.path());
}

// --- Job files --------------------------------------------------------------------------------

TEST(JobFile, KeysValuesAndLines) {
  const TempFile job("plain.toml",
                     "[solve]\n# comment\nrays = 4096\nscene = \"a # b.obj\"  # not the value\n");
  const std::vector<JobOption> options = readJobFile(job.path());
  ASSERT_EQ(options.size(), 2u);
  EXPECT_EQ(options[0].key, "rays");
  EXPECT_EQ(options[0].value, "4096");
  EXPECT_EQ(options[0].line, 3);
  EXPECT_EQ(options[1].key, "scene");
  EXPECT_EQ(options[1].value, "a # b.obj");
  EXPECT_EQ(options[1].line, 4);
}

// Every TOML spelling of a value becomes the text CLI11 parses, in the order of the file.
TEST(JobFile, EveryTomlValueForm) {
  const TempFile job("forms.toml",
                     "scene = 'C:\\scenes\\room.obj'  # literal: no escapes\n"
                     "output = \"a \\\"b\\\" \\u00e9 # c.h5\"\n"
                     "checkpoint = \"\"\"\nfirst\nsecond\"\"\"\n"
                     "restart = '''\nraw \\n'''\n"
                     "[solve]\n"
                     "rays = 4_096\nseed = 0xff\npatches = 0o17\nthreads = 0b101\n"
                     "rtol = 1e-3\nmax-area = 0.1\ndrop-threshold = +2.5E2\n"
                     "target-error = nan\ncheckpoint-every = -inf\n"
                     "quiet = true\nreciprocity = false\n");
  const std::vector<std::pair<std::string, std::string>> expected{
      {"scene", "C:\\scenes\\room.obj"},
      {"output", "a \"b\" \xc3\xa9 # c.h5"},
      {"checkpoint", "first\nsecond"},
      {"restart", "raw \\n"},
      {"rays", "4096"},
      {"seed", "255"},
      {"patches", "15"},
      {"threads", "5"},
      {"rtol", "0.001"},
      {"max-area", "0.1"},
      {"drop-threshold", "250"},
      {"target-error", "nan"},
      {"checkpoint-every", "-inf"},
      {"quiet", "true"},
      {"reciprocity", "false"}};
  const std::vector<JobOption> options = readJobFile(job.path());
  ASSERT_EQ(options.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(options[i].key, expected[i].first);
    EXPECT_EQ(options[i].value, expected[i].second) << options[i].key;
  }
  EXPECT_EQ(options[3].line, 6);  // a multi-line value: the line of its key
  EXPECT_EQ(options[4].line, 9);
  EXPECT_EQ(options.back().line, 19);
}

// The message of the InputError that reading `text` as a job file throws, after the file's path.
std::string refusal(const std::string& text) {
  const TempFile job("refused.toml", text);
  const Error e = thrownBy([&] { readJobFile(job.path()); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  const std::string message = e.what();
  EXPECT_EQ(message.rfind(job.path() + ":", 0), 0u) << message;
  return message.substr(std::min(message.size(), job.path().size()));
}

TEST(JobFile, DuplicateKeyRefusedWithFileAndLine) {
  EXPECT_EQ(refusal("rays = 64\nseed = 2\nrays = 128\n"),
            ":3: 'rays' is given twice (first on line 1)");
  EXPECT_EQ(refusal("rays = 64\n[solve]\nseed = 2\n\nrays = 128\n"),
            ":5: 'rays' is given twice (first on line 1)");
  EXPECT_EQ(refusal("[solve]\nseed = 2\n\n\"seed\" = 3\n"),
            ":4: 'seed' is given twice (first on line 2)");
  EXPECT_EQ(refusal("[solve]\nrays = 1\n[solve]\nseed = 2\n"),
            ":3: 'solve' is given twice (first on line 1)");
  // Twice on one line: toml++'s own words, with the column.
  EXPECT_EQ(refusal("\nrays = 1\nx = {a = 1, a = 2}\n").rfind(":3:17: ", 0), 0u);
}

TEST(JobFile, TablesArraysAndDatesRefusedWithFileAndLine) {
  EXPECT_EQ(refusal("rays = 1\n[render]\nwidth = 3\n"),
            ":2: 'render' must be a single value, found a table (a job file holds solve options, "
            "at the top or in [solve])");
  EXPECT_EQ(refusal("rays = 1\nseed = [1, 2]\n"),
            ":2: 'seed' must be a single value, found an array");
  EXPECT_EQ(refusal("[[solve]]\nrays = 1\n"),
            ":1: 'solve' must be a single value, found an array of tables");
  EXPECT_EQ(refusal("rays = {x = 1}\n"), ":1: 'rays' must be a single value, found a table");
  EXPECT_EQ(refusal("quiet = true\nrays.x = 1\n").rfind(":2: 'rays' must be a single value", 0),
            0u);
  EXPECT_EQ(refusal("[solve]\nrays = 1\n[solve.more]\nx = 1\n"),
            ":3: 'solve.more' must be a single value, found a table");
  EXPECT_EQ(refusal("[solve]\nseed.x = 1\n"),
            ":2: 'solve.seed' must be a single value, found a table");
  EXPECT_EQ(refusal("seed = 1979-05-27\n"),
            ":1: 'seed' must be a string, a number or true or false, found a date");
}

TEST(JobFile, SyntaxErrorsRefusedWithLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"rays 64\n", ":1:6: error while parsing key-value pair"},
      {"\n= 64\n", ":2:1: "},
      {"rays =\n", ":1:7: "},
      {"quiet = yes\n", ":1:9: "},
      {"rays = abc\n", ":1:8: "},
      {"# job\nscene = \"open\n", ":2:14: error while parsing string"},
      {"scene = 'open\nrays = 1\n", ":1:14: "},
      {"scene = \"\"\"open\nrays = 1\n",
       ":2:10: error while parsing string: encountered end-of-file"},
      {"output = \"a \\q\"\n", ":1:14: error while parsing string: unknown escape"},
      {"seed = 18446744073709551615\n", ":1:28: "},
      {"rays = 1\n\x7f"
       "ELF\x02\n",
       ":2:"}};
  for (const auto& [text, expected] : cases) {
    const std::string message = refusal(text);
    EXPECT_EQ(message.rfind(expected, 0), 0u) << text << " -> " << message;
  }
  EXPECT_NE(refusal("scene = \"open\n").find("is a closing quote missing?"), std::string::npos);
  EXPECT_NE(refusal("seed = 18446744073709551615\n").find("in quotes"), std::string::npos);
  EXPECT_NE(refusal("solver = gmres\n").find("text goes in quotes"), std::string::npos);
}

// TOML spells a NUL "\\u0000"; C names end there (a result written to "a" for "a\\u0000b.h5"),
// so a string holding one is refused with its line.
TEST(JobFile, NulInAStringRefusedWithItsLine) {
  const TempFile job("nul.toml", "rays = 16\n\noutput = \"a\\u0000b.h5\"\n");
  const Error e = thrownBy([&] { readJobFile(job.path()); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_EQ(std::string(e.what()).rfind(job.path() + ":3: 'output' holds a NUL", 0), 0u)
      << e.what();
}

TEST(JobFile, MissingFileAndDirectoryRefused) {
  EXPECT_EQ(thrownBy([] { readJobFile("/nonexistent/job.toml"); }).exitCode(),
            exit_code::kBadInput);
  const Error e = thrownBy([] { readJobFile("/tmp"); });
  EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
}

// --- Checkpoint identity ----------------------------------------------------------------------

// The unit box of tests/test_scenes.h: 12 patches.
Mesh box() { return testing::closedBox(0.5, 1.0); }

Checkpoint savedBy(const SolveSettings& settings, const Mesh& mesh, double maxArea) {
  Checkpoint saved;
  saved.identity = runIdentity(settings, mesh, maxArea);
  saved.patchCount = mesh.triangleCount();
  saved.rows.rowSamples.assign(mesh.triangles.size(), settings.raysPerPatch);
  return saved;
}

TEST(CheckpointIdentity, SameRunResumesAndRaysMayGrow) {
  SolveSettings settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  EXPECT_NO_THROW(checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 1024));
  settings.raysPerPatch = 4096;  // not part of the identity
  EXPECT_NO_THROW(checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 4096));
}

TEST(CheckpointIdentity, ChangedOptionRefusedAndNamed) {
  SolveSettings settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  settings.seed = 2;
  Error e =
      thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 1024); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("; seed: 1 there, 2 now"), std::string::npos) << e.what();
  settings.seed = 1;
  settings.estimator = formfactor::Estimator::kEmitterMis;
  e = thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 1024); });
  EXPECT_NE(std::string(e.what()).find("estimator: auto there, mis now"), std::string::npos);
  settings.estimator = std::nullopt;  // "auto"
  e = thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.25), 12, 1024); });
  EXPECT_NE(std::string(e.what()).find("max-area: 0.5 there, 0.25 now"), std::string::npos);
}

// A checkpoint of MIS rows drawn with another light choice (or before lights were chosen) must
// not be extended with rows drawn this way: the sums would mix two estimators.
TEST(CheckpointIdentity, CheckpointOfAnotherLightChoiceRefused) {
  SolveSettings settings;
  const Mesh mesh = box();
  Checkpoint saved = savedBy(settings, mesh, 0.5);
  saved.identity.erase("mis light choice");
  const Error e =
      thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 1024); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("mis light choice: (none) there, per 64 patches"),
            std::string::npos)
      << e.what();
}

TEST(CheckpointIdentity, ChangedGeometryRefused) {
  const SolveSettings settings;
  const Checkpoint saved = savedBy(settings, box(), 0.5);
  Mesh moved = box();
  moved.vertices[0].x += 1e-9;
  const Error e =
      thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, moved, 0.5), 12, 1024); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("; scene: 12 patches, hash"), std::string::npos) << e.what();
}

// F depends on the geometry only: other materials are no refusal, but said (the solve runs
// again); the same materials are not.
TEST(CheckpointIdentity, ChangedMaterialsAreSaidNotRefused) {
  const SolveSettings settings;
  const Checkpoint saved = savedBy(settings, box(), 0.5);
  Mesh brighter = box();
  brighter.reflectance[5][1] = 0.6;
  EXPECT_TRUE(checkResumable("c.h5", saved, runIdentity(settings, brighter, 0.5), 12, 1024));
  Mesh lit = box();
  lit.emission[0][2] = 3;
  EXPECT_TRUE(checkResumable("c.h5", saved, runIdentity(settings, lit, 0.5), 12, 1024));
  EXPECT_FALSE(checkResumable("c.h5", saved, runIdentity(settings, box(), 0.5), 12, 1024));
}

TEST(CheckpointIdentity, FewerRaysThanSavedRefused) {
  const SolveSettings settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  const Error e =
      thrownBy([&] { checkResumable("c.h5", saved, runIdentity(settings, mesh, 0.5), 12, 512); });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("more than --rays 512"), std::string::npos) << e.what();
}

// --- Safe points ------------------------------------------------------------------------------

void (*currentHandler(int signal))(int) {
  struct sigaction action {};
  sigaction(signal, nullptr, &action);
  return action.sa_handler;
}

TEST(SafePoints, DisabledLeavesSignalsAlone) {
  SafePoints safePoints(MPI_COMM_WORLD, false, 1e-9);
  EXPECT_EQ(currentHandler(SIGTERM), SIG_DFL);
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
}

TEST(SafePoints, SignalStopsAtTheNextPollAndHandlersAreRestored) {
  {
    SafePoints safePoints(MPI_COMM_WORLD, true, 0);
    EXPECT_NE(currentHandler(SIGUSR1), SIG_DFL);
    EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
    std::raise(SIGUSR1);  // only sets the flag: the test goes on
    EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kStop);
    EXPECT_EQ(safePoints.stopReason(), "SIGUSR1");
  }
  for (int signal : {SIGTERM, SIGINT, SIGUSR1}) EXPECT_EQ(currentHandler(signal), SIG_DFL);
  // A new run starts without the old request.
  SafePoints again(MPI_COMM_WORLD, true, 0);
  EXPECT_EQ(again.poll(), solve::SafePointAction::kContinue);
}

// Loading and meshing are one long stretch before the first safe point: a signal in it is seen
// there, and the stretch does not count as one between safe points (it would bring a
// --stop-after stop forward by the time of the load).
TEST(SafePoints, StopRequestedSeesASignalFromBeforeTheFirstSafePoint) {
  SafePoints safePoints(MPI_COMM_WORLD, true, 0, 10.0, MPI_Wtime());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // "loading"
  EXPECT_FALSE(safePoints.stopRequested());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
  std::raise(SIGTERM);
  EXPECT_TRUE(safePoints.stopRequested());
  EXPECT_EQ(safePoints.stopReason(), "SIGTERM");
}

TEST(SafePoints, PeriodicCheckpointDueAfterItsInterval) {
  SafePoints safePoints(MPI_COMM_WORLD, true, 0.05);
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kSave);
  safePoints.checkpointWritten();
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
}

TEST(SafePoints, StopAfterStopsWhileTheNextStretchAndAWriteStillFit) {
  // 1 s allowed. After 0.2 s, with stretches of 0.2 s between safe points, it goes on; after
  // another stretch of 0.6 s, a third such stretch would overrun: it stops. (Margins wide enough
  // for a loaded machine: a late wake-up only makes the stop more certain.)
  SafePoints safePoints(MPI_COMM_WORLD, true, 0, 1.0, MPI_Wtime());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kStop);
  EXPECT_EQ(safePoints.stopReason(), "--stop-after 1 s");
}

TEST(SafePoints, StopAfterLeavesRoomForTheLongestCheckpointWrite) {
  SafePoints safePoints(MPI_COMM_WORLD, true, 0.01, 1.0, MPI_Wtime());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(safePoints.poll(), solve::SafePointAction::kSave);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // a slow checkpoint write
  safePoints.checkpointWritten();
  // 0.52 s gone, stretches of 0.02 s, but a write takes 0.5 s: stopping now is the last chance.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kStop);
}

// --- Durations (--stop-after) -----------------------------------------------------------------

TEST(Duration, FormsBatchUsersWrite) {
  EXPECT_EQ(parseDuration("5400"), 5400);
  EXPECT_EQ(parseDuration("90s"), 90);
  EXPECT_EQ(parseDuration("90m"), 5400);
  EXPECT_EQ(parseDuration("1.5h"), 5400);
  EXPECT_EQ(parseDuration("3h50m"), 13800);
  EXPECT_EQ(parseDuration("1h30m15s"), 5415);
  EXPECT_EQ(parseDuration("2d"), 172800);
  EXPECT_EQ(parseDuration("0.25"), 0.25);
  EXPECT_EQ(parseDuration("03:50:00"), 13800);  // PBS walltime, SLURM --time
  EXPECT_EQ(parseDuration("45:30"), 2730);      // SLURM MM:SS
  EXPECT_EQ(parseDuration("1-12:00:00"), 129600);
  EXPECT_EQ(parseDuration("1000000000"), 1e9);  // the longest: about 31 years
}

TEST(Duration, AmbiguousEmptyOrHugeRefused) {
  for (const char* text : {"",      "0",        "0s",   "-5",         "1h30",
                           "30m1h", "1m1m",     "5 m",  "inf",        "nan",
                           "1e3",   "12:60:00", "1:99", "1-30:00",    "abc",
                           "3h50x", ":",        "1::2", "1000000001", "99999999999999999999d",
                           "20000d"})
    EXPECT_FALSE(parseDuration(text).has_value()) << text;
}

TEST(Duration, Described) {
  EXPECT_EQ(describeDuration(13800), "3h 50m");
  EXPECT_EQ(describeDuration(90061), "1d 1h 1m 1s");
  EXPECT_EQ(describeDuration(4), "4 s");
}

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

// --- What the solve derives from its settings -------------------------------------------------

TEST(SolveSettings, DefaultOutputIsTheScenesName) {
  EXPECT_EQ(defaultOutput("builtin:box?rho=0.9&n=3"), "box.h5");
  EXPECT_EQ(defaultOutput("builtin:cornell"), "cornell.h5");
  EXPECT_EQ(defaultOutput("scenes/room.obj"), "room.h5");
  EXPECT_EQ(defaultOutput("scenes/room.h5"), "room.result.h5");  // not the scene's own name
}

TEST(SolveSettings, NextRayCountGrowsWithinBounds) {
  EXPECT_EQ(nextRayCount(1024, 0.01, 1), 2048);                         // at least doubled
  EXPECT_EQ(nextRayCount(1024, 100, 0.01), 16 * 1024);                  // at most ×16
  EXPECT_EQ(nextRayCount(int64_t{1} << 24, 1, 0.1), int64_t{1} << 24);  // at most 2^24
}

TEST(SolveSettings, SamplingOptionsNameTheEstimator) {
  SolveSettings settings;
  settings.estimator = formfactor::Estimator::kEmitterMis;
  settings.raysPerPatch = 77;
  EXPECT_EQ(samplingOptions(settings).estimator, formfactor::Estimator::kEmitterMis);
  EXPECT_EQ(samplingOptions(settings).raysPerPatch, 77);
  settings.estimator = formfactor::Estimator::kHemisphere;
  EXPECT_EQ(samplingOptions(settings).estimator, formfactor::Estimator::kHemisphere);
}

TEST(StageReports, WindingWarningAboveTwoPercentOfTheRaysNamesTheLabelsMostHit) {
  const std::vector<std::string> names = {"floor", "wall (group a)", "table", "shelf"};
  EXPECT_EQ(windingWarning(1000, 20, {0, 15, 5, 0}, names), "");
  EXPECT_EQ(windingWarning(0, 0, {0, 0, 0, 0}, names), "");
  const std::string warning = windingWarning(1000, 40, {0, 10, 30, 0}, names);
  EXPECT_EQ(warning.rfind("4.0% of the rays hit the back of a face", 0), 0u) << warning;
  EXPECT_NE(warning.find("most hit: 'table' 75%, 'wall (group a)' 25%"), std::string::npos)
      << warning;
  EXPECT_EQ(warning.find("floor"), std::string::npos) << warning;
  // Without labels, the share alone.
  EXPECT_EQ(windingWarning(100, 50, {}, {}).find("most hit"), std::string::npos);
}

}  // namespace
}  // namespace radiosity::jobs

namespace radiosity::jobs {
namespace {

// --- Outputs and their temporaries ------------------------------------------------------------

// A name the file system or Open MPI's MPI-IO cannot take with its temporary, and a directory on
// a kernel file system, are refused before any work (exit 2), not at the write.
TEST(OutputPaths, LimitsAndKernelFileSystemsRefusedUpFront) {
  const std::string folder = std::filesystem::temp_directory_path().string();
  const std::string longName = folder + "/" + std::string(240, 'x') + ".h5";
  Error e = thrownBy([&] { checkOutputs({longName}, {}); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("the name is too long"), std::string::npos) << e.what();
  const std::string mpiName = std::string(200, 'y') + ".h5";  // fine for the file system
  EXPECT_NO_THROW(checkOutputs({mpiName}, {}));
  e = thrownBy([&] { checkMpiIoOutputs({mpiName}); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("too long for MPI-IO"), std::string::npos) << e.what();
  EXPECT_NO_THROW(checkMpiIoOutputs({"result.h5", ""}));
  for (const char* path : {"/proc/x.h5", "/sys/x.h5", "/dev/x.h5"}) {
    e = thrownBy([&] { checkOutputs({path}, {}); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << path;
    EXPECT_NE(std::string(e.what()).find("cannot write here"), std::string::npos) << e.what();
  }
  e = thrownBy([&] { checkOutputs({std::string("a\0b.h5", 6)}, {}); });
  EXPECT_NE(std::string(e.what()).find("NUL"), std::string::npos) << e.what();
  // The temporary of such a name was the cut name itself, and the search for a free one never
  // ended once that existed.
  e = thrownBy([&] { temporaryNameFor(std::string("a\0b.h5", 6)); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
}

// Temporaries carry host and pid; only those of a process that is gone (on this host) are stale.
// The older form without a host is still ours.
TEST(OutputPaths, OnlyTemporariesOfGoneProcessesAreStale) {
  const std::string host = hostField();
  const std::string own = temporaryNameFor("/tmp/out.h5");
  EXPECT_EQ(
      own.rfind("/tmp/out.h5.tmp.radiosity-" + host + "-" + std::to_string(::getpid()) + "-", 0),
      0u)
      << own;
  EXPECT_TRUE(isOurTemporary(own, "/tmp/out.h5"));
  EXPECT_FALSE(isStaleTemporary(own, "/tmp/out.h5"));  // this process: alive
  // A pid beyond any kernel's pid_max (2^22) never runs: its temporaries are stale.
  const std::string gone = "out.h5.tmp.radiosity-" + host + "-9999999-0badcafe";
  EXPECT_TRUE(isStaleTemporary(gone, "out.h5"));
  const std::string parent =
      "out.h5.tmp.radiosity-" + host + "-" + std::to_string(::getppid()) + "-0badcafe";
  EXPECT_TRUE(isOurTemporary(parent, "out.h5"));
  EXPECT_FALSE(isStaleTemporary(parent, "out.h5"));  // alive: it may be writing now
  EXPECT_FALSE(isStaleTemporary("out.h5.tmp.radiosity-" + host + "x-9999999-0badcafe", "out.h5"))
      << "another host's cannot be told";
  EXPECT_TRUE(isOurTemporary("out.h5.tmp.radiosity-9999999-0badcafe", "out.h5"));  // older form
  EXPECT_TRUE(isStaleTemporary("out.h5.tmp.radiosity-9999999-0badcafe", "out.h5"));
  // Open MPI's lock test beside a temporary, left by a rank killed while opening it.
  EXPECT_TRUE(isStaleTemporary(gone + ".locktest.1", "out.h5"));
  EXPECT_FALSE(isStaleTemporary(parent + ".locktest.0", "out.h5"));  // alive
  EXPECT_FALSE(isStaleTemporary(gone + ".locktest.", "out.h5"));
  EXPECT_FALSE(isStaleTemporary(gone + ".locktest.x", "out.h5"));
  EXPECT_TRUE(isOurTemporary("out.h5.tmp.radiosity-node-7.a_b-12-0badcafe", "out.h5"));
  for (const char* name :
       {"out.h5.tmp.radiosity-12-0BADCAFE", "out.h5.tmp.radiosity--12-0badcafe",
        "out.h5.tmp.radiosity-h-x1-0badcafe", "out.h5.tmp.notes", "out.h5.tmp.radiosity-12-0bad"})
    EXPECT_FALSE(isOurTemporary(name, "out.h5")) << name;
}

// A batch job's memory limit (SLURM's --mem, a container's) bounds what the run may use, not
// the node's physical memory: each cgroup layout as the kernel writes it, read from a tree laid
// out like /sys/fs/cgroup.
class CgroupMemoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::temp_directory_path() /
            ("radiosity_cgroup_" + std::to_string(getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }
  void write(const std::filesystem::path& file, const std::string& text) {
    std::filesystem::create_directories((root_ / file).parent_path());
    std::ofstream(root_ / file) << text;
  }
  std::filesystem::path root_;
};

TEST_F(CgroupMemoryTest, VersionOneTakesTheTightestOfTheCgroupAndItsAncestors) {
  const std::string self = "9:name=systemd:/\n4:cpu,memory:/slurm/uid_0/job_7/step_0\n0::/\n";
  write("memory/memory.limit_in_bytes", "9223372036854771712\n");  // the root: unlimited
  write("memory/slurm/uid_0/job_7/memory.limit_in_bytes", "8589934592\n");
  write("memory/slurm/uid_0/job_7/step_0/memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_EQ(cgroupMemoryLimit(self, root_), 8589934592.0);
  write("memory/slurm/uid_0/job_7/step_0/memory.limit_in_bytes", "2147483648\n");
  EXPECT_EQ(cgroupMemoryLimit(self, root_), 2147483648.0);
}

TEST_F(CgroupMemoryTest, VersionTwoReadsMemoryMaxAndMaxMeansNone) {
  const std::string self = "0::/system.slice/job.scope\n";
  write("system.slice/job.scope/memory.max", "max\n");
  EXPECT_EQ(cgroupMemoryLimit(self, root_), 0.0);
  write("system.slice/memory.max", "4294967296\n");
  EXPECT_EQ(cgroupMemoryLimit(self, root_), 4294967296.0);
  write("system.slice/job.scope/memory.max", "1073741824\n");
  EXPECT_EQ(cgroupMemoryLimit(self, root_), 1073741824.0);
}

TEST_F(CgroupMemoryTest, ANamespacedCgroupIsReadAtTheRootAndGarbageIsNoLimit) {
  // Inside a cgroup namespace /proc/self/cgroup names the host's path, which is not there: the
  // mounted root is the process's own cgroup.
  write("memory.max", "3221225472\n");
  EXPECT_EQ(cgroupMemoryLimit("0::/host/path/not/mounted\n", root_), 3221225472.0);
  EXPECT_EQ(cgroupMemoryLimit("0::/\n", root_), 3221225472.0);
  write("memory.max", "12 GB\n");
  EXPECT_EQ(cgroupMemoryLimit("0::/\n", root_), 0.0);
  write("memory.max", "-1\n");
  EXPECT_EQ(cgroupMemoryLimit("0::/\n", root_), 0.0);
  EXPECT_EQ(cgroupMemoryLimit("", root_), 0.0);
  EXPECT_EQ(cgroupMemoryLimit("garbage without colons\n", root_), 0.0);
  EXPECT_EQ(cgroupMemoryLimit("0::/\n", root_ / "absent"), 0.0);
  // This machine: never more than its physical memory, and something.
  const double physical =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  EXPECT_GT(nodeMemoryBytes(), 0.0);
  EXPECT_LE(nodeMemoryBytes(), physical);
}

}  // namespace
}  // namespace radiosity::jobs
