// Checkpoint and restart as batch jobs use them: a signal before the time limit, a killed rank,
// a kill in the middle of a checkpoint write, restarts on other rank counts. Every restarted run
// must equal an uninterrupted one: F bit for bit, B to the solver's tolerance.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "checkpoint_run_fixture.h"
#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "obj_room.h"
#include "program_runner.h"

namespace radiosity {
namespace {

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
  ASSERT_NO_FATAL_FAILURE(runWholeAndStopAtRefine(options));
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_EQ(stageOf(path("ck.h5")), "formfactors");
  EXPECT_NE(describeCheckpoint(path("ck.h5")).find("refinement rounds: 1 ("), std::string::npos)
      << describeCheckpoint(path("ck.h5"));
  ASSERT_NO_FATAL_FAILURE(restartOnThree(options));
  const Result whole = readResult(path("whole.h5")), out = readResult(path("out.h5"));
  EXPECT_EQ(out.mesh.triangles, whole.mesh.triangles);
  expectSameAnswer(out, whole);
}

// A --target-error round that raised the rays, stopped as its refined mesh is laid out (its rows
// not sampled yet): the restart on 3 ranks goes on at the round's rays (it went on at --rays,
// 2e-4 off the uninterrupted B) and ends with the uninterrupted run's mesh and answer.
TEST_F(Checkpoints, AStopAfterATargetErrorRoundThatRaisedTheRaysThenRestartOnThreeRanks) {
  testing::writeRoomObj(
      path("room.obj"), path("room.mtl"), "newmtl lamp\nKd 0 0 0\nKe 20 20 20\n",
      {{"lamp",
        {{{1.75, 2.99, 1.75}, {2.25, 2.99, 1.75}, {2.25, 2.99, 2.25}, {1.75, 2.99, 2.25}}}}});
  const std::string options = "solve " + path("room.obj") +
                              " --target-error 1e-5 --max-area 0.2 --max-patches 1300 --rays 16 "
                              "--save-formfactors -q --checkpoint ";
  ASSERT_NO_FATAL_FAILURE(runWholeAndStopAtRefine(options));
  ASSERT_NO_FATAL_FAILURE(restartOnThree(options));
  const Result whole = readResult(path("whole.h5")), out = readResult(path("out.h5"));
  EXPECT_EQ(out.attributes.raysPerPatch, whole.attributes.raysPerPatch);
  EXPECT_GT(whole.attributes.raysPerPatch, 256);
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

}  // namespace
}  // namespace radiosity
