// What the end-to-end tests (end_to_end_*_test.cpp) share: a fresh directory per test with the
// program run in it on R ranks, a solve figure of a result, and a closed box written as OBJ+MTL.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/result.h"
#include "program_runner.h"
#include "test_scenes.h"

namespace radiosity::testing {

class EndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("radiosity-e2e-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs the program on `ranks` ranks (through mpiexec, as root and oversubscribed if need be).
  ProgramRun radiosity(int ranks, const std::string& arguments) const {
    return runProgram(ranks, arguments, path("log.txt"));
  }

  // `solve --threads T` + `options` + a new file, on each (ranks, T) of `splits`; the results in
  // that order (call it under ASSERT_NO_FATAL_FAILURE).
  void solveOnEach(const std::vector<std::pair<int, int>>& splits, const std::string& options,
                   std::vector<Result>& results) const {
    for (auto [ranks, threads] : splits) {
      const std::string out = path(std::to_string(ranks) + "x" + std::to_string(threads) + ".h5");
      ProgramRun run =
          radiosity(ranks, "solve --threads " + std::to_string(threads) + options + out);
      ASSERT_EQ(run.exitCode, 0) << run.output;
      results.push_back(readResult(out));
    }
  }

  std::filesystem::path dir_;
};

/// The solve figure `name` of `result`, -1 if it has none.
inline double figure(const Result& result, const std::string& name) {
  auto found = result.attributes.solveFigures.find(name);
  return found == result.attributes.solveFigures.end() ? -1 : found->second;
}

// A closed box whose faces are given their own ρ and E, written as OBJ+MTL.
inline std::string writeBox(const std::string& objPath, const std::vector<Rgb>& faceReflectance,
                            const std::vector<Rgb>& faceEmission) {
  Mesh box = closedBox(0.5, 0.0);
  for (size_t t = 0; t < box.triangles.size(); ++t) {
    box.reflectance[t] = faceReflectance[box.sourceFace[t]];
    box.emission[t] = faceEmission[box.sourceFace[t]];
  }
  writeSceneObj(box, objPath);
  return objPath;
}

}  // namespace radiosity::testing
