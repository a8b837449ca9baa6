// Unit tests of the radiosity_jobs library's inputs and outputs, without running a command: job
// files (TOML, alone and beside the command line), what the solve derives from its settings, and
// the outputs and their temporaries. Runs on one rank (Console needs MPI).
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
#include "test_scenes.h"

namespace radiosity::jobs {
namespace {

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

// --- What the solve derives from its settings -------------------------------------------------

TEST(SolveRequest, DefaultOutputIsTheScenesName) {
  EXPECT_EQ(run::defaultOutput("builtin:box?rho=0.9&n=3"), "box.h5");
  EXPECT_EQ(run::defaultOutput("builtin:cornell"), "cornell.h5");
  EXPECT_EQ(run::defaultOutput("scenes/room.obj"), "room.h5");
  EXPECT_EQ(run::defaultOutput("scenes/room.h5"), "room.result.h5");  // not the scene's own name
}

TEST(SolveRequest, NextRayCountGrowsWithinBounds) {
  EXPECT_EQ(run::nextRayCount(1024, 0.01, 1), 2048);                         // at least doubled
  EXPECT_EQ(run::nextRayCount(1024, 100, 0.01), 16 * 1024);                  // at most ×16
  EXPECT_EQ(run::nextRayCount(int64_t{1} << 24, 1, 0.1), int64_t{1} << 24);  // at most 2^24
}

TEST(SolveRequest, SamplingOptionsNameTheEstimator) {
  run::SolveRequest settings;
  settings.estimator = formfactor::Estimator::kEmitterMis;
  settings.raysPerPatch = 77;
  const run::RunPlan plan = run::initialPlan(settings);
  EXPECT_EQ(run::samplingOptions(settings, plan).estimator, formfactor::Estimator::kEmitterMis);
  EXPECT_EQ(run::samplingOptions(settings, plan).raysPerPatch, 77);
  settings.estimator = formfactor::Estimator::kHemisphere;
  EXPECT_EQ(run::samplingOptions(settings, run::initialPlan(settings)).estimator,
            formfactor::Estimator::kHemisphere);
}

TEST(StageReports, WindingWarningAboveTwoPercentOfTheRaysNamesTheLabelsMostHit) {
  const std::vector<std::string> names = {"floor", "wall (group a)", "table", "shelf"};
  EXPECT_EQ(run::windingWarning(1000, 20, {0, 15, 5, 0}, names), "");
  EXPECT_EQ(run::windingWarning(0, 0, {0, 0, 0, 0}, names), "");
  const std::string warning = run::windingWarning(1000, 40, {0, 10, 30, 0}, names);
  EXPECT_EQ(warning.rfind("4.0% of the rays hit the back of a face", 0), 0u) << warning;
  EXPECT_NE(warning.find("most hit: 'table' 75%, 'wall (group a)' 25%"), std::string::npos)
      << warning;
  EXPECT_EQ(warning.find("floor"), std::string::npos) << warning;
  // Without labels, the share alone.
  EXPECT_EQ(run::windingWarning(100, 50, {}, {}).find("most hit"), std::string::npos);
}

// Nearly every ray out of the scene: hardly anything sees anything, as in a room wound inside
// out; half of them (an open city) is no reason to warn.
TEST(StageReports, EscapeWarningOnlyWhereNearlyEveryRayLeaves) {
  EXPECT_EQ(run::escapeWarning(1000, 500), "");
  EXPECT_EQ(run::escapeWarning(1000, 990), "");
  EXPECT_EQ(run::escapeWarning(0, 0), "");
  const std::string warning = run::escapeWarning(1000, 1000);
  EXPECT_NE(warning.find("100.0% of the rays left the scene"), std::string::npos) << warning;
  EXPECT_NE(warning.find("counter-clockwise"), std::string::npos) << warning;
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
  Error e = thrownBy([&] { run::checkOutputs({longName}, {}); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("the name is too long"), std::string::npos) << e.what();
  const std::string mpiName = std::string(200, 'y') + ".h5";  // fine for the file system
  EXPECT_NO_THROW(run::checkOutputs({mpiName}, {}));
  e = thrownBy([&] { run::checkMpiIoOutputs({mpiName}); });
  EXPECT_EQ(e.exitCode(), exit_code::kUsage);
  EXPECT_NE(std::string(e.what()).find("too long for MPI-IO"), std::string::npos) << e.what();
  EXPECT_NO_THROW(run::checkMpiIoOutputs({"result.h5", ""}));
  for (const char* path : {"/proc/x.h5", "/sys/x.h5", "/dev/x.h5"}) {
    e = thrownBy([&] { run::checkOutputs({path}, {}); });
    EXPECT_EQ(e.exitCode(), exit_code::kUsage) << path;
    EXPECT_NE(std::string(e.what()).find("cannot write here"), std::string::npos) << e.what();
  }
  e = thrownBy([&] { run::checkOutputs({std::string("a\0b.h5", 6)}, {}); });
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
  EXPECT_EQ(run::cgroupMemoryLimit(self, root_), 8589934592.0);
  write("memory/slurm/uid_0/job_7/step_0/memory.limit_in_bytes", "2147483648\n");
  EXPECT_EQ(run::cgroupMemoryLimit(self, root_), 2147483648.0);
}

TEST_F(CgroupMemoryTest, VersionTwoReadsMemoryMaxAndMaxMeansNone) {
  const std::string self = "0::/system.slice/job.scope\n";
  write("system.slice/job.scope/memory.max", "max\n");
  EXPECT_EQ(run::cgroupMemoryLimit(self, root_), 0.0);
  write("system.slice/memory.max", "4294967296\n");
  EXPECT_EQ(run::cgroupMemoryLimit(self, root_), 4294967296.0);
  write("system.slice/job.scope/memory.max", "1073741824\n");
  EXPECT_EQ(run::cgroupMemoryLimit(self, root_), 1073741824.0);
}

TEST_F(CgroupMemoryTest, ANamespacedCgroupIsReadAtTheRootAndGarbageIsNoLimit) {
  // Inside a cgroup namespace /proc/self/cgroup names the host's path, which is not there: the
  // mounted root is the process's own cgroup.
  write("memory.max", "3221225472\n");
  EXPECT_EQ(run::cgroupMemoryLimit("0::/host/path/not/mounted\n", root_), 3221225472.0);
  EXPECT_EQ(run::cgroupMemoryLimit("0::/\n", root_), 3221225472.0);
  write("memory.max", "12 GB\n");
  EXPECT_EQ(run::cgroupMemoryLimit("0::/\n", root_), 0.0);
  write("memory.max", "-1\n");
  EXPECT_EQ(run::cgroupMemoryLimit("0::/\n", root_), 0.0);
  EXPECT_EQ(run::cgroupMemoryLimit("", root_), 0.0);
  EXPECT_EQ(run::cgroupMemoryLimit("garbage without colons\n", root_), 0.0);
  EXPECT_EQ(run::cgroupMemoryLimit("0::/\n", root_ / "absent"), 0.0);
  // This machine: never more than its physical memory, and something.
  const double physical =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  EXPECT_GT(run::nodeMemoryBytes(), 0.0);
  EXPECT_LE(run::nodeMemoryBytes(), physical);
}

}  // namespace
}  // namespace radiosity::jobs
