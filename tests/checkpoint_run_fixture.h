// What the checkpoint-and-restart tests (checkpoint_test.cpp, checkpoint_reuse_test.cpp) share:
// the long runs a signal can land in, a fresh directory per test with its runs' logs, the
// comparisons of a restarted answer with an uninterrupted one, and the ranks of a background run.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "program_runner.h"

namespace radiosity {

namespace fs = std::filesystem;
using testing::BackgroundRun;
using testing::ProgramRun;

// A form-factor stage of a few seconds on 2 ranks (1480 patches × 16384 rays), so that a signal
// lands inside it; rows are saved so that F can be compared bit for bit.
inline constexpr char kLongSampling[] =
    "builtin:cornell --max-area 2000 --rays 16384 --estimator hemisphere --rtol 1e-10 "
    "--balance cost "
    "--save-formfactors";
// A solve of a few seconds: shooting in a box of reflectance 0.999 (~23 000 batches).
inline constexpr char kLongSolve[] =
    "'builtin:box?rho=0.999&e=1' --max-area 0.02 --rays 64 --solver southwell --rtol 1e-10 "
    "--save-formfactors -q";

// The ranks of a background run (below).
inline std::vector<pid_t> ranksOf(pid_t mpiexec);

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

  // Whether the last background run reached the stage stall of the test hook
  // (RADIOSITY_TEST_STAGE_STALL) within 120 s.
  bool stalled(BackgroundRun* job) {
    const std::string log = path("log" + std::to_string(runs_) + ".txt");
    return job->waitUntil(
        [&] { return testing::readText(log).find("test hook: stalling") != std::string::npos; },
        120);
  }

  // `options` (ending in --checkpoint) run whole on 2 ranks into whole.h5, then again stopped
  // by SIGTERM as a refinement round's mesh is laid out (the test hook's stall): ck.h5, exit 75.
  void runWholeAndStopAtRefine(const std::string& options) {
    ASSERT_EQ(run(2, options + path("whole-ck.h5") + " -o " + path("whole.h5")).exitCode, 0);
    BackgroundRun* job = start(2, options + path("ck.h5") + " -o " + path("out.h5"),
                               "RADIOSITY_TEST_STAGE_STALL='refine 4'");
    ASSERT_TRUE(stalled(job));
    for (pid_t rank : ranksOf(job->pid())) kill(rank, SIGTERM);
    ProgramRun stopped = job->wait();
    ASSERT_EQ(stopped.exitCode, 75) << stopped.output;
  }

  // The stopped run of runWholeAndStopAtRefine restarted on 3 ranks into out.h5.
  void restartOnThree(const std::string& options) {
    ProgramRun restarted =
        run(3, options + path("ck.h5") + " --restart " + path("ck.h5") + " -o " + path("out.h5"));
    ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
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
inline void expectSameAnswer(const Result& restarted, const Result& uninterrupted) {
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
inline void expectCloseAnswer(const Result& a, const Result& b, double valueGap,
                              double radiosityGap) {
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
inline std::vector<pid_t> ranksOf(pid_t mpiexec) {
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

}  // namespace radiosity
