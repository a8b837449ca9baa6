// Checkpoint and restart as batch jobs use them: a signal before the time limit, a killed rank,
// a kill in the middle of a checkpoint write, restarts on other rank counts, more rays later.
// Every restarted run must equal an uninterrupted one: F bit for bit, B to the solver's
// tolerance.
#include <gtest/gtest.h>

#include <dirent.h>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "io/store/checkpoint.h"
#include "io/store/checkpoint_format.h"
#include "io/store/hdf5_read.h"
#include "io/store/result.h"
#include "program_runner.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::BackgroundRun;
using testing::ProgramRun;

// A form-factor stage of a few seconds on 2 ranks (1480 patches × 16384 rays), so that a signal
// lands inside it; rows are saved so that F can be compared bit for bit.
constexpr char kLongSampling[] =
    "builtin:cornell --max-area 2000 --rays 16384 --estimator hemisphere --rtol 1e-10 "
    "--balance cost "
    "--save-formfactors";
// A solve of a few seconds: shooting in a box of reflectance 0.999 (~23 000 batches).
constexpr char kLongSolve[] =
    "'builtin:box?rho=0.999&e=1' --max-area 0.02 --rays 64 --solver southwell --rtol 1e-10 "
    "--save-formfactors -q";

class Checkpoints : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("radiosity-checkpoint-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  ProgramRun run(int ranks, const std::string& arguments) {
    return testing::runProgram(ranks, arguments, path("log" + std::to_string(++runs_) + ".txt"));
  }
  BackgroundRun* start(int ranks, const std::string& arguments,
                       const std::string& environment = "") {
    background_.push_back(std::make_unique<BackgroundRun>(
        ranks, arguments, path("log" + std::to_string(++runs_) + ".txt"), environment));
    return background_.back().get();
  }

  // The stage a checkpoint file was written in ("" while there is none).
  static std::string stageOf(const std::string& file) {
    if (!fs::exists(file) || !isCheckpoint(file)) return "";
    const std::string text = describeCheckpoint(file);
    const size_t at = text.find("stage: ");
    return at == std::string::npos ? "?" : text.substr(at + 7, text.find('\n', at) - at - 7);
  }

  fs::path dir_;
  int runs_ = 0;
  std::vector<std::unique_ptr<BackgroundRun>> background_;
};

// F bit for bit; B within the solver's tolerance (its error bound is ~1e-10 here).
void expectSameAnswer(const Result& restarted, const Result& uninterrupted) {
  ASSERT_TRUE(restarted.formFactors.has_value());
  ASSERT_TRUE(uninterrupted.formFactors.has_value());
  EXPECT_EQ(restarted.formFactors->rowStart, uninterrupted.formFactors->rowStart);
  EXPECT_EQ(restarted.formFactors->column, uninterrupted.formFactors->column);
  EXPECT_TRUE(restarted.formFactors->value == uninterrupted.formFactors->value)
      << "form factors differ";
  ASSERT_EQ(restarted.radiosity.size(), uninterrupted.radiosity.size());
  double largest = 0, gap = 0;
  for (size_t i = 0; i < uninterrupted.radiosity.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      largest = std::max(largest, std::abs(uninterrupted.radiosity[i][c]));
      gap = std::max(gap, std::abs(restarted.radiosity[i][c] - uninterrupted.radiosity[i][c]));
    }
  }
  EXPECT_LE(gap, 1e-8 * largest);
}

// The same rows with F's values and B within the relative gaps given.
void expectCloseAnswer(const Result& a, const Result& b, double valueGap, double radiosityGap) {
  ASSERT_TRUE(a.formFactors.has_value());
  ASSERT_TRUE(b.formFactors.has_value());
  EXPECT_EQ(a.formFactors->rowStart, b.formFactors->rowStart);
  ASSERT_EQ(a.formFactors->column, b.formFactors->column);
  double gap = 0;
  for (size_t k = 0; k < a.formFactors->value.size(); ++k)
    gap = std::max(
        gap, std::abs(a.formFactors->value[k] - b.formFactors->value[k]) / b.formFactors->value[k]);
  EXPECT_LE(gap, valueGap);
  EXPECT_GT(gap, 0);  // (rounded: not the double run's property)
  ASSERT_EQ(a.radiosity.size(), b.radiosity.size());
  double largest = 0;
  gap = 0;
  for (size_t i = 0; i < b.radiosity.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      largest = std::max(largest, std::abs(b.radiosity[i][c]));
      gap = std::max(gap, std::abs(a.radiosity[i][c] - b.radiosity[i][c]));
    }
  }
  EXPECT_LE(gap, radiosityGap * largest);
}

// The ranks of a background run: the children of mpiexec that run the program.
std::vector<pid_t> ranksOf(pid_t mpiexec) {
  std::vector<pid_t> ranks;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string pid, command, state;
    long parent = 0;
    stat >> pid >> command >> state >> parent;
    if (parent == mpiexec && command.find("radiosity") != std::string::npos)
      ranks.push_back(std::stoi(pid));
  }
  return ranks;
}

TEST_F(Checkpoints, SigtermInTheFormFactorStageThenRestartOnOneAndOnThreeRanks) {
  ASSERT_EQ(run(2, "solve " + std::string(kLongSampling) + " -o " + path("whole.h5")).exitCode, 0);
  BackgroundRun* job = start(2, "solve " + std::string(kLongSampling) + " --checkpoint " +
                                    path("ck.h5") + " --checkpoint-every 0.3 -o " + path("out.h5"));
  ASSERT_TRUE(job->waitUntil([&] { return stageOf(path("ck.h5")) == "formfactors"; }, 120))
      << "no checkpoint in the form-factor stage";
  // SIGTERM to every rank, as a scheduler signals the tasks of a job step.
  for (pid_t rank : ranksOf(job->pid())) kill(rank, SIGTERM);
  ProgramRun stopped = job->wait();
  ASSERT_EQ(stopped.exitCode, 75) << stopped.output;
  EXPECT_NE(stopped.output.find("stopped by SIGTERM"), std::string::npos) << stopped.output;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_EQ(stageOf(path("ck.h5")), "formfactors");
  EXPECT_EQ(describeCheckpoint(path("ck.h5")).find("rows sampled: 1480 of 1480"), std::string::npos)
      << "the stop came after the last row";
  // The checkpoint's blocks were cut by measured cost on 2 ranks; the restart on 3 cuts its own.
  EXPECT_NE(stopped.output.find("balance: blocks by measured cost"), std::string::npos)
      << stopped.output;

  const Result whole = readResult(path("whole.h5"));
  for (int ranks : {1, 3}) {
    const std::string copy = path("ck" + std::to_string(ranks) + ".h5");
    fs::copy_file(path("ck.h5"), copy);
    const std::string out = path("restarted" + std::to_string(ranks) + ".h5");
    ProgramRun restarted = run(ranks, "solve " + std::string(kLongSampling) + " --restart " + copy +
                                          " --checkpoint " + copy + " -o " + out);
    ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
    EXPECT_NE(restarted.output.find("restart: "), std::string::npos) << restarted.output;
    if (ranks > 1) {
      EXPECT_NE(restarted.output.find("balance: blocks by measured cost"), std::string::npos)
          << restarted.output;
    }
    expectSameAnswer(readResult(out), whole);
  }
}

TEST_F(Checkpoints, SigtermInTheSolveThenRestartOnOneAndOnThreeRanks) {
  ASSERT_EQ(run(2, "solve " + std::string(kLongSolve) + " -o " + path("whole.h5")).exitCode, 0);
  BackgroundRun* job = start(2, "solve " + std::string(kLongSolve) + " --checkpoint " +
                                    path("ck.h5") + " --checkpoint-every 0.2 -o " + path("out.h5"));
  ASSERT_TRUE(job->waitUntil([&] { return stageOf(path("ck.h5")) == "solve"; }, 120))
      << "no checkpoint in the solve";
  for (pid_t rank : ranksOf(job->pid())) kill(rank, SIGTERM);
  ProgramRun stopped = job->wait();
  ASSERT_EQ(stopped.exitCode, 75) << stopped.output;
  EXPECT_EQ(stageOf(path("ck.h5")), "solve");
  EXPECT_NE(describeCheckpoint(path("ck.h5")).find("in progress"), std::string::npos);

  const Result whole = readResult(path("whole.h5"));
  for (int ranks : {1, 3}) {
    const std::string copy = path("ck" + std::to_string(ranks) + ".h5");
    fs::copy_file(path("ck.h5"), copy);
    const std::string out = path("restarted" + std::to_string(ranks) + ".h5");
    ProgramRun restarted =
        run(ranks, "solve " + std::string(kLongSolve) + " --restart " + copy + " -o " + out);
    ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
    const Result result = readResult(out);
    expectSameAnswer(result, whole);
    for (const Rgb& b : result.radiosity) ASSERT_NEAR(b[0], 1000.0, 1e-6 * 1000);
    // The history goes on where the stopped run left it.
    ASSERT_GT(result.attributes.history.size(), 2u);
    EXPECT_GT(result.attributes.history.iteration.back(), result.attributes.iterations);
  }
}

// SIGUSR1 to mpiexec, as the batch templates send it: mpiexec forwards it to every rank and
// exits with their 75.
// Whether `pid` is a process that runs (not gone, not a zombie waiting to be reaped).
bool processLives(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string id, command, state;
  if (!(stat >> id >> command >> state)) return false;
  return state != "Z" && state != "X";
}

// Once mpiexec is gone its ranks may still be dying; their temporaries are stale only once they
// are (the cleanup keeps the temporaries of live processes: they may be another run's).
void waitUntilGone(const std::vector<pid_t>& ranks) {
  for (pid_t rank : ranks) {
    for (int k = 0; k < 500 && processLives(rank); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

TEST_F(Checkpoints, SigusrOneToMpiexecStopsTheRunWithACheckpoint) {
  BackgroundRun* job = start(2, "solve " + std::string(kLongSampling) + " --checkpoint " +
                                    path("ck.h5") + " --checkpoint-every 0.3 -o " + path("out.h5"));
  ASSERT_TRUE(job->waitUntil([&] { return stageOf(path("ck.h5")) == "formfactors"; }, 120));
  job->signal(SIGUSR1);
  ProgramRun stopped = job->wait();
  EXPECT_EQ(stopped.exitCode, 75) << stopped.output;
  EXPECT_NE(stopped.output.find("stopped by SIGUSR1"), std::string::npos) << stopped.output;
  EXPECT_EQ(stageOf(path("ck.h5")), "formfactors");
  EXPECT_FALSE(fs::exists(path("out.h5")));
}

// A signal while the scene loads or is meshed (test hook: the ranks stall at the end of the
// stage) stops the run at the first safe point with exit 75 and a checkpoint that records
// nothing sampled, so that a batch job requeues; the restart, on another rank count, gives the
// uninterrupted answer.
TEST_F(Checkpoints, SignalsWhileLoadingOrMeshingStopWithACheckpoint) {
  const std::string options =
      "solve builtin:cornell --patches 300 --rays 16 --save-formfactors -q --checkpoint ";
  ASSERT_EQ(run(2, options + path("whole-ck.h5") + " -o " + path("whole.h5")).exitCode, 0);
  const std::pair<int, const char*> signals[] = {
      {SIGUSR1, "SIGUSR1"}, {SIGTERM, "SIGTERM"}, {SIGINT, "SIGINT"}};
  for (const char* stage : {"load", "mesh"}) {
    for (const auto& [number, name] : signals) {
      SCOPED_TRACE(std::string(name) + " at the end of stage " + stage);
      const std::string checkpoint = path(std::string(stage) + "-" + name + ".h5");
      BackgroundRun* job = start(2, options + checkpoint + " -o " + path("out.h5"),
                                 "RADIOSITY_TEST_STAGE_STALL='" + std::string(stage) + " 4'");
      const std::string log = path("log" + std::to_string(runs_) + ".txt");
      ASSERT_TRUE(job->waitUntil(
          [&] { return testing::readText(log).find("test hook: stalling") != std::string::npos; },
          120));
      // SIGUSR1 to mpiexec, which forwards it; SIGTERM and SIGINT to the ranks, as a scheduler
      // signals the tasks of a job step.
      if (number == SIGUSR1) {
        job->signal(SIGUSR1);
      } else {
        for (pid_t rank : ranksOf(job->pid())) kill(rank, number);
      }
      ProgramRun stopped = job->wait();
      EXPECT_EQ(stopped.exitCode, 75) << stopped.output;
      EXPECT_NE(stopped.output.find(std::string("stopped by ") + name), std::string::npos)
          << stopped.output;
      EXPECT_FALSE(fs::exists(path("out.h5")));
      EXPECT_EQ(stageOf(checkpoint), "formfactors");
      EXPECT_NE(describeCheckpoint(checkpoint).find("rows sampled: 0 of 300"), std::string::npos)
          << describeCheckpoint(checkpoint);
    }
  }
  ProgramRun restarted = run(3, options + path("mesh-SIGTERM.h5") + " --restart " +
                                    path("mesh-SIGTERM.h5") + " -o " + path("out.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  expectSameAnswer(readResult(path("out.h5")), readResult(path("whole.h5")));
}

// A stop inside an adaptive refinement round (a signal as the refined mesh is laid out: test
// hook) keeps the rounds done: the checkpoint records them, and a restart on 3 ranks replays
// them, samples the new mesh's rows and goes on to the uninterrupted run's mesh and answer.
TEST_F(Checkpoints, AStopInsideARefinementRoundThenRestartOnThreeRanks) {
  const std::string options =
      "solve builtin:cornell --max-area 4000 --rays 256 --refine-rounds 2 --save-formfactors -q "
      "--checkpoint ";
  ASSERT_EQ(run(2, options + path("whole-ck.h5") + " -o " + path("whole.h5")).exitCode, 0);
  BackgroundRun* job = start(2, options + path("ck.h5") + " -o " + path("out.h5"),
                             "RADIOSITY_TEST_STAGE_STALL='refine 4'");
  const std::string log = path("log" + std::to_string(runs_) + ".txt");
  ASSERT_TRUE(job->waitUntil(
      [&] { return testing::readText(log).find("test hook: stalling") != std::string::npos; },
      120));
  for (pid_t rank : ranksOf(job->pid())) kill(rank, SIGTERM);
  ProgramRun stopped = job->wait();
  ASSERT_EQ(stopped.exitCode, 75) << stopped.output;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_EQ(stageOf(path("ck.h5")), "formfactors");
  EXPECT_NE(describeCheckpoint(path("ck.h5")).find("refinement rounds: 1 ("), std::string::npos)
      << describeCheckpoint(path("ck.h5"));
  ProgramRun restarted =
      run(3, options + path("ck.h5") + " --restart " + path("ck.h5") + " -o " + path("out.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  const Result whole = readResult(path("whole.h5")), out = readResult(path("out.h5"));
  EXPECT_EQ(out.mesh.triangles, whole.mesh.triangles);
  expectSameAnswer(out, whole);
}

// --stop-after: no signal at all; the run stops on its own clock with a checkpoint, and the
// restart (on another rank count) gives the uninterrupted answer.
TEST_F(Checkpoints, StopAfterStopsOnItsOwnClockAndTheRestartGivesTheSameAnswer) {
  ASSERT_EQ(run(2, "solve " + std::string(kLongSampling) + " -o " + path("whole.h5")).exitCode, 0);
  ProgramRun stopped = run(2, "solve " + std::string(kLongSampling) + " --checkpoint " +
                                  path("ck.h5") + " --stop-after 0.5 -o " + path("out.h5"));
  ASSERT_EQ(stopped.exitCode, 75) << stopped.output;
  EXPECT_NE(stopped.output.find("radiosity: stopped by --stop-after 0.5 s"), std::string::npos)
      << stopped.output;
  // A stop that was asked for is no error.
  EXPECT_EQ(stopped.output.find("error:"), std::string::npos) << stopped.output;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_EQ(stageOf(path("ck.h5")), "formfactors");
  ProgramRun restarted =
      run(3, "solve " + std::string(kLongSampling) + " --restart " + path("ck.h5") +
                 " --checkpoint " + path("ck.h5") + " -o " + path("out.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  expectSameAnswer(readResult(path("out.h5")), readResult(path("whole.h5")));
}

TEST_F(Checkpoints, AKilledRankLosesOnlyTheWorkSinceTheLastPeriodicCheckpoint) {
  ASSERT_EQ(run(2, "solve " + std::string(kLongSampling) + " -o " + path("whole.h5")).exitCode, 0);
  BackgroundRun* job = start(2, "solve " + std::string(kLongSampling) + " --checkpoint " +
                                    path("ck.h5") + " --checkpoint-every 0.3 -o " + path("out.h5"));
  ASSERT_TRUE(job->waitUntil([&] { return stageOf(path("ck.h5")) == "formfactors"; }, 120));
  const std::vector<pid_t> ranks = ranksOf(job->pid());
  ASSERT_EQ(ranks.size(), 2u);
  kill(ranks[1], SIGKILL);  // a node dies: mpiexec takes the whole job down
  ProgramRun killed = job->wait();
  EXPECT_NE(killed.exitCode, 0);
  EXPECT_NE(killed.exitCode, 75);
  EXPECT_FALSE(fs::exists(path("out.h5")));
  ASSERT_NE(stageOf(path("ck.h5")), "");

  ProgramRun restarted = run(2, "solve " + std::string(kLongSampling) + " --restart " +
                                    path("ck.h5") + " -o " + path("out.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  expectSameAnswer(readResult(path("out.h5")), readResult(path("whole.h5")));
}

// A rank killed while the result is being written (test hook: the ranks stall between the
// complete temporary and its rename) leaves no result, only our temporary (and, where the kill
// came while MPI-IO opened it, Open MPI's lock test beside it), which the next successful run to
// the same output removes.
TEST_F(Checkpoints, AKilledRankLeavesNoResultAndTheNextRunCleansUp) {
  const std::string options = " builtin:cornell --max-area 8000 --rays 64 -q ";
  BackgroundRun* job =
      start(2, "solve" + options + "-o " + path("out.h5"), "RADIOSITY_TEST_RESULT_STALL=60");
  auto temporaries = [&](bool lockTests) {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      if (lockTests || name.find(".locktest.") == std::string::npos)
        count += name.rfind("out.h5.tmp.radiosity-", 0) == 0 ? 1 : 0;
    }
    return count;
  };
  ASSERT_TRUE(job->waitUntil([&] { return temporaries(false) > 0; }, 120));
  const std::vector<pid_t> ranks = ranksOf(job->pid());
  ASSERT_EQ(ranks.size(), 2u);
  kill(ranks[1], SIGKILL);
  ProgramRun killed = job->wait();
  waitUntilGone(ranks);
  EXPECT_NE(killed.exitCode, 0);
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_EQ(temporaries(false), 1) << "the killed write's temporary is left (SIGKILL)";

  ProgramRun again = run(2, "solve" + options + "-o " + path("out.h5"));
  ASSERT_EQ(again.exitCode, 0) << again.output;
  EXPECT_TRUE(fs::exists(path("out.h5")));
  EXPECT_EQ(temporaries(true), 0) << "the next successful write removes the stale temporaries";
}

TEST_F(Checkpoints, AKillInTheMiddleOfACheckpointWriteLeavesThePreviousOneUsable) {
  const std::string options = " builtin:cornell --max-area 8000 --rays 256 --save-formfactors -q ";
  ASSERT_EQ(run(2, "solve" + options + "--checkpoint " + path("ck.h5") + " -o " + path("whole.h5"))
                .exitCode,
            0);
  fs::copy_file(path("ck.h5"), path("before.h5"));
  // The restart's own checkpoint write stalls (test hook) after its data went to the
  // temporary file; the job is killed there.
  BackgroundRun* job = start(2,
                             "solve" + options + "--restart " + path("ck.h5") + " --checkpoint " +
                                 path("ck.h5") + " -o " + path("out.h5"),
                             "RADIOSITY_TEST_CHECKPOINT_STALL=60");
  auto temporaryExists = [&] {
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename().string().rfind("ck.h5.tmp", 0) == 0) return true;
    return false;
  };
  ASSERT_TRUE(job->waitUntil(temporaryExists, 120)) << "the checkpoint write never started";
  const std::vector<pid_t> ranks = ranksOf(job->pid());
  job->signal(SIGKILL, true);
  job->wait();
  waitUntilGone(ranks);
  EXPECT_EQ(testing::readText(path("ck.h5")), testing::readText(path("before.h5")));
  EXPECT_TRUE(temporaryExists()) << "the killed write's temporary file is left (SIGKILL)";
  ProgramRun restarted = run(2, "solve" + options + "--restart " + path("ck.h5") +
                                    " --checkpoint " + path("ck.h5") + " -o " + path("again.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  expectSameAnswer(readResult(path("again.h5")), readResult(path("whole.h5")));
  EXPECT_FALSE(temporaryExists()) << "the next checkpoint write removes the stale temporary";
}

TEST_F(Checkpoints, CorruptedCheckpointsAndCheckpointsOfOtherOptionsAreRefused) {
  const std::string options = " builtin:cornell --max-area 8000 --rays 64 -q ";
  ASSERT_EQ(
      run(2, "solve" + options + "--checkpoint " + path("ck.h5") + " -o " + path("a.h5")).exitCode,
      0);
  // Other options: named, exit 3, no output.
  ProgramRun seed =
      run(2, "solve" + options + "--seed 2 --restart " + path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(seed.exitCode, 3) << seed.output;
  EXPECT_NE(seed.output.find("seed: 1 there, 2 now"), std::string::npos) << seed.output;
  ProgramRun scene = run(2, "solve builtin:cornell --max-area 4000 --rays 64 -q --restart " +
                                path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(scene.exitCode, 3) << scene.output;
  EXPECT_NE(scene.output.find("patches"), std::string::npos) << scene.output;
  ProgramRun fewer = run(2, "solve builtin:cornell --max-area 8000 --rays 32 -q --restart " +
                                path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(fewer.exitCode, 3) << fewer.output;
  EXPECT_NE(fewer.output.find("--rays"), std::string::npos) << fewer.output;
  EXPECT_FALSE(fs::exists(path("b.h5")));

  // Corrupted: bytes flipped in the middle of the file, where the rows are.
  std::string bytes = testing::readText(path("ck.h5"));
  for (size_t k = bytes.size() / 2; k < bytes.size() / 2 + 64; ++k)
    bytes[k] = static_cast<char>(~bytes[k]);
  std::ofstream(path("corrupt.h5"), std::ios::binary) << bytes;
  ProgramRun corrupt =
      run(2, "solve" + options + "--restart " + path("corrupt.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(corrupt.exitCode, 3) << corrupt.output;
  EXPECT_NE(corrupt.output.find("corrupt"), std::string::npos) << corrupt.output;
  // Truncated.
  std::ofstream(path("truncated.h5"), std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  ProgramRun truncated =
      run(2, "solve" + options + "--restart " + path("truncated.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(truncated.exitCode, 3) << truncated.output;
  EXPECT_FALSE(fs::exists(path("b.h5")));
}

// With F's values in double precision the extended rows are a fresh run's bit for bit; in
// single precision (the default here) the first rows' sums come back rounded, so F and B are a
// fresh run's to that rounding (2^-24 of each value).
TEST_F(Checkpoints, MoreRaysLaterEqualAFreshRunWithThatManyRays) {
  std::string scene = " builtin:cornell --max-area 4000 --rtol 1e-10 --save-formfactors ";
  {
    const std::string single = scene + "--formfactor-precision single ";
    ASSERT_EQ(run(2, "solve" + single + "--rays 64 --checkpoint " + path("s.ck.h5") + " -o " +
                         path("s64.h5"))
                  .exitCode,
              0);
    ProgramRun more = run(3, "solve" + single + "--rays 160 --restart " + path("s.ck.h5") + " -o " +
                                 path("smore.h5"));
    ASSERT_EQ(more.exitCode, 0) << more.output;
    ASSERT_EQ(run(2, "solve" + single + "--rays 160 -o " + path("sfresh.h5")).exitCode, 0);
    expectCloseAnswer(readResult(path("smore.h5")), readResult(path("sfresh.h5")), 0x1p-23, 1e-6);
  }
  scene += "--formfactor-precision double ";
  ASSERT_EQ(
      run(2, "solve" + scene + "--rays 64 --checkpoint " + path("ck.h5") + " -o " + path("64.h5"))
          .exitCode,
      0);
  EXPECT_EQ(stageOf(path("ck.h5")), "done");
  ProgramRun more = run(3, "solve" + scene + "--rays 160 --restart " + path("ck.h5") +
                               " --checkpoint " + path("ck.h5") + " -o " + path("more.h5"));
  ASSERT_EQ(more.exitCode, 0) << more.output;
  EXPECT_NE(more.output.find("given more samples"), std::string::npos) << more.output;
  ASSERT_EQ(run(2, "solve" + scene + "--rays 160 -o " + path("fresh.h5")).exitCode, 0);
  expectSameAnswer(readResult(path("more.h5")), readResult(path("fresh.h5")));
  // info shows what the checkpoint holds.
  ProgramRun info = run(1, "info " + path("ck.h5"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("stage: done"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("160"), std::string::npos) << info.output;
}

// F is stored once during the solve (PETSc's matrix) and its tally rebuilt from it for the
// checkpoints; a solver that works on the matrix in place (gauss-seidel) keeps a copy instead.
// The final checkpoints' rows must be the same tally either way, and the rebuilt one must serve
// a restart with more rays.
TEST_F(Checkpoints, TheRowsRebuiltFromTheSolversMatrixAreTheSampledRows) {
  // (in double precision: single-precision values give their sums back rounded,
  // single_precision_test)
  const std::string scene =
      " builtin:cornell --max-area 4000 --rtol 1e-10 --save-formfactors -q "
      "--formfactor-precision double ";
  for (const char* solver : {"gmres", "gauss-seidel"}) {
    const std::string name = solver;
    ProgramRun solved = run(2, "solve" + scene + "--rays 64 --solver " + name + " --checkpoint " +
                                   path(name + ".ck.h5") + " -o " + path(name + ".h5"));
    ASSERT_EQ(solved.exitCode, 0) << solved.output;
    EXPECT_EQ(stageOf(path(name + ".ck.h5")), "done");
  }
  // (read serially: MPI in this process would be inherited by the mpiexec it starts)
  auto dataset = [&](const std::string& file, const char* name) {
    h5::Handle opened = h5::openFile(path(file), "checkpoint");
    int64_t rows = -1;
    return h5::readDataset<int64_t>(opened.get(), path(file), name, H5T_NATIVE_INT64, 0, rows);
  };
  for (const char* name : {checkpoint_format::kSamples, checkpoint_format::kRowStart,
                           checkpoint_format::kColumn, checkpoint_format::kSum}) {
    const std::vector<int64_t> rebuilt = dataset("gmres.ck.h5", name),
                               kept = dataset("gauss-seidel.ck.h5", name);
    EXPECT_GT(kept.size(), 100u) << name;
    EXPECT_TRUE(rebuilt == kept) << name << " differs";
  }

  // (Checkpoints from inside the solve: SigtermInTheSolveThenRestartOnOneAndOnThreeRanks.)

  // More rays from the rebuilt rows equal a fresh run with that many.
  ProgramRun more = run(3, "solve" + scene + "--rays 96 --solver gmres --restart " +
                               path("gmres.ck.h5") + " -o " + path("more.h5"));
  ASSERT_EQ(more.exitCode, 0) << more.output;
  ASSERT_EQ(run(2, "solve" + scene + "--rays 96 --solver gmres -o " + path("fresh.h5")).exitCode,
            0);
  expectSameAnswer(readResult(path("more.h5")), readResult(path("fresh.h5")));
}

// A job file can hold every option, the scene and the checkpoint ones included; the plain
// mpirun template runs it to the end.
TEST_F(Checkpoints, AJobFileHoldsEveryOptionAndTheMpirunTemplateRunsIt) {
  std::ofstream(path("job.toml")) << "# a batch job\n[solve]\nscene = \"builtin:cornell\"\n"
                                  << "output = \"" << path("job.h5") << "\"\nmax-area = 8000\n"
                                  << "rays = 64\nsolver = \"cg\"\ncheckpoint = \""
                                  << path("job.ckpt.h5") << "\"\ncheckpoint-every = 0\n"
                                  << "quiet = true\n";
  ProgramRun direct = run(2, "solve --config " + path("job.toml"));
  ASSERT_EQ(direct.exitCode, 0) << direct.output;
  EXPECT_EQ(readResult(path("job.h5")).attributes.solver, "cg");
  EXPECT_EQ(stageOf(path("job.ckpt.h5")), "done");

  fs::remove(path("job.h5"));
  const std::string script = std::string(SOURCE_DIR) + "/jobs/templates/run_until_done.sh";
  const std::string command =
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
      "OMPI_MCA_rmaps_base_oversubscribe=1 NP=2 "
      "RADIOSITY=" RADIOSITY_BINARY " CHECKPOINT=" +
      path("template.ckpt.h5") + " bash " + script + " " + path("job.toml") + " > " +
      path("template.log") + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << testing::readText(path("template.log"));
  EXPECT_TRUE(fs::exists(path("job.h5")));
}

}  // namespace
}  // namespace radiosity
