// Unit tests of how a run of `radiosity solve` is controlled (run/), without running one: the
// identity that ties a checkpoint to its run (and lets other materials reuse its form factors),
// the safe points where signals are acted on, and the durations of --stop-after. The requests are
// made as the command line makes them (jobs_fixture.h's parse). Runs on one rank (SafePoints need
// MPI).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>

#include "core/error.h"
#include "jobs_fixture.h"
#include "mpi_environment.h"
#include "run/checkpointing.h"
#include "run/duration.h"
#include "run/safe_points.h"
#include "test_scenes.h"

namespace radiosity::jobs {
namespace {

// --- Checkpoint identity ----------------------------------------------------------------------

// The unit box of tests/test_scenes.h: 12 patches.
Mesh box() { return testing::closedBox(0.5, 1.0); }

Checkpoint savedBy(const run::SolveRequest& settings, const Mesh& mesh, double maxArea) {
  Checkpoint saved;
  saved.identity = run::runIdentity(settings, run::initialPlan(settings), mesh, maxArea);
  saved.patchCount = mesh.triangleCount();
  saved.rows.rowSamples.assign(mesh.triangles.size(), settings.raysPerPatch);
  return saved;
}

TEST(CheckpointIdentity, SameRunResumesAndRaysMayGrow) {
  run::SolveRequest settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  EXPECT_NO_THROW(run::checkResumable(
      "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 1024));
  settings.raysPerPatch = 4096;  // not part of the identity
  EXPECT_NO_THROW(run::checkResumable(
      "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 4096));
}

TEST(CheckpointIdentity, ChangedOptionRefusedAndNamed) {
  run::SolveRequest settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  settings.seed = 2;
  Error e = thrownBy([&] {
    run::checkResumable(
        "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 1024);
  });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("; seed: 1 there, 2 now"), std::string::npos) << e.what();
  settings.seed = 1;
  settings.estimator = formfactor::Estimator::kEmitterMis;
  e = thrownBy([&] {
    run::checkResumable(
        "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 1024);
  });
  EXPECT_NE(std::string(e.what()).find("estimator: auto there, mis now"), std::string::npos);
  settings.estimator = std::nullopt;  // "auto"
  e = thrownBy([&] {
    run::checkResumable("c.h5", saved,
                        run::runIdentity(settings, run::initialPlan(settings), mesh, 0.25), 12,
                        1024);
  });
  EXPECT_NE(std::string(e.what()).find("max-area: 0.5 there, 0.25 now"), std::string::npos);
}

// A checkpoint of MIS rows drawn with another light choice (or before lights were chosen) must
// not be extended with rows drawn this way: the sums would mix two estimators.
TEST(CheckpointIdentity, CheckpointOfAnotherLightChoiceRefused) {
  run::SolveRequest settings;
  const Mesh mesh = box();
  Checkpoint saved = savedBy(settings, mesh, 0.5);
  saved.identity.erase("mis light choice");
  const Error e = thrownBy([&] {
    run::checkResumable(
        "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 1024);
  });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("mis light choice: (none) there, per 64 patches"),
            std::string::npos)
      << e.what();
}

TEST(CheckpointIdentity, ChangedGeometryRefused) {
  const run::SolveRequest settings;
  const Checkpoint saved = savedBy(settings, box(), 0.5);
  Mesh moved = box();
  moved.vertices[0].x += 1e-9;
  const Error e = thrownBy([&] {
    run::checkResumable("c.h5", saved,
                        run::runIdentity(settings, run::initialPlan(settings), moved, 0.5), 12,
                        1024);
  });
  EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
  EXPECT_NE(std::string(e.what()).find("; scene: 12 patches, hash"), std::string::npos) << e.what();
}

// F depends on the geometry only: other materials are no refusal, but said (the solve runs
// again); the same materials are not.
TEST(CheckpointIdentity, ChangedMaterialsAreSaidNotRefused) {
  const run::SolveRequest settings;
  const Checkpoint saved = savedBy(settings, box(), 0.5);
  Mesh brighter = box();
  brighter.reflectance[5][1] = 0.6;
  EXPECT_TRUE(run::checkResumable(
      "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), brighter, 0.5), 12,
      1024));
  Mesh lit = box();
  lit.emission[0][2] = 3;
  EXPECT_TRUE(run::checkResumable(
      "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), lit, 0.5), 12, 1024));
  EXPECT_FALSE(run::checkResumable(
      "c.h5", saved, run::runIdentity(settings, run::initialPlan(settings), box(), 0.5), 12, 1024));
}

TEST(CheckpointIdentity, FewerRaysThanSavedRefused) {
  const run::SolveRequest settings;
  const Mesh mesh = box();
  const Checkpoint saved = savedBy(settings, mesh, 0.5);
  const Error e = thrownBy([&] {
    run::checkResumable("c.h5", saved,
                        run::runIdentity(settings, run::initialPlan(settings), mesh, 0.5), 12, 512);
  });
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
  run::SafePoints safePoints(MPI_COMM_WORLD, false, 1e-9);
  EXPECT_EQ(currentHandler(SIGTERM), SIG_DFL);
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
}

TEST(SafePoints, SignalStopsAtTheNextPollAndHandlersAreRestored) {
  {
    run::SafePoints safePoints(MPI_COMM_WORLD, true, 0);
    EXPECT_NE(currentHandler(SIGUSR1), SIG_DFL);
    EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
    std::raise(SIGUSR1);  // only sets the flag: the test goes on
    EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kStop);
    EXPECT_EQ(safePoints.stopReason(), "SIGUSR1");
  }
  for (int signal : {SIGTERM, SIGINT, SIGUSR1}) EXPECT_EQ(currentHandler(signal), SIG_DFL);
  // A new run starts without the old request.
  run::SafePoints again(MPI_COMM_WORLD, true, 0);
  EXPECT_EQ(again.poll(), solve::SafePointAction::kContinue);
}

// Loading and meshing are one long stretch before the first safe point: a signal in it is seen
// there, and the stretch does not count as one between safe points (it would bring a
// --stop-after stop forward by the time of the load).
TEST(SafePoints, StopRequestedSeesASignalFromBeforeTheFirstSafePoint) {
  run::SafePoints safePoints(MPI_COMM_WORLD, true, 0, 10.0, MPI_Wtime());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // "loading"
  EXPECT_FALSE(safePoints.stopRequested());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
  std::raise(SIGTERM);
  EXPECT_TRUE(safePoints.stopRequested());
  EXPECT_EQ(safePoints.stopReason(), "SIGTERM");
}

TEST(SafePoints, PeriodicCheckpointDueAfterItsInterval) {
  run::SafePoints safePoints(MPI_COMM_WORLD, true, 0.05);
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
  run::SafePoints safePoints(MPI_COMM_WORLD, true, 0, 1.0, MPI_Wtime());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kContinue);
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  EXPECT_EQ(safePoints.poll(), solve::SafePointAction::kStop);
  EXPECT_EQ(safePoints.stopReason(), "--stop-after 1 s");
}

TEST(SafePoints, StopAfterLeavesRoomForTheLongestCheckpointWrite) {
  run::SafePoints safePoints(MPI_COMM_WORLD, true, 0.01, 1.0, MPI_Wtime());
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
  EXPECT_EQ(run::parseDuration("5400"), 5400);
  EXPECT_EQ(run::parseDuration("90s"), 90);
  EXPECT_EQ(run::parseDuration("90m"), 5400);
  EXPECT_EQ(run::parseDuration("1.5h"), 5400);
  EXPECT_EQ(run::parseDuration("3h50m"), 13800);
  EXPECT_EQ(run::parseDuration("1h30m15s"), 5415);
  EXPECT_EQ(run::parseDuration("2d"), 172800);
  EXPECT_EQ(run::parseDuration("0.25"), 0.25);
  EXPECT_EQ(run::parseDuration("03:50:00"), 13800);  // PBS walltime, SLURM --time
  EXPECT_EQ(run::parseDuration("45:30"), 2730);      // SLURM MM:SS
  EXPECT_EQ(run::parseDuration("1-12:00:00"), 129600);
  EXPECT_EQ(run::parseDuration("1000000000"), 1e9);  // the longest: about 31 years
}

TEST(Duration, AmbiguousEmptyOrHugeRefused) {
  for (const char* text : {"",      "0",        "0s",   "-5",         "1h30",
                           "30m1h", "1m1m",     "5 m",  "inf",        "nan",
                           "1e3",   "12:60:00", "1:99", "1-30:00",    "abc",
                           "3h50x", ":",        "1::2", "1000000001", "99999999999999999999d",
                           "20000d"})
    EXPECT_FALSE(run::parseDuration(text).has_value()) << text;
}

TEST(Duration, Described) {
  EXPECT_EQ(run::describeDuration(13800), "3h 50m");
  EXPECT_EQ(run::describeDuration(90061), "1d 1h 1m 1s");
  EXPECT_EQ(run::describeDuration(4), "4 s");
}

}  // namespace
}  // namespace radiosity::jobs
