// What the scene-input tests (io_scene_*_test.cpp) share: a fresh folder to write scene files
// into, the check that an InputError names what the user must fix, and checks of a mesh's
// warnings, vertices, closure and orientation.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"

namespace radiosity::testing {

/// A fresh folder per test, removed afterwards.
class SceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = std::filesystem::temp_directory_path() /
           ("io_scene_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Writes `content` byte for byte to `name` inside the test folder; returns the full path.
  std::string write(const std::string& name, const std::string& content) {
    const std::filesystem::path path = dir_ / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << content;
    return path.string();
  }

  std::filesystem::path dir_;
};

/// Runs `f`, expects an InputError (exit code 3) whose message contains every one of `parts`.
inline void expectInputError(const std::function<void()>& f,
                             const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
    for (const auto& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
    }
  }
}

inline bool hasWarningWith(const Mesh& mesh, const std::string& text) {
  for (const auto& w : mesh.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

inline void expectNear(Vec3 a, Vec3 b, double tolerance = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

/// Every directed edge appears once and its reverse once: closed and consistently oriented.
inline bool closedAndOriented(const Mesh& mesh) {
  std::map<std::pair<int64_t, int64_t>, int> directed;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != 1) return false;
  }
  return true;
}

/// Signed volume enclosed (divergence theorem): negative when the normals point inward.
inline double signedVolume(const Mesh& mesh) {
  double v = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    v += dot(mesh.corner(t, 0), cross(mesh.corner(t, 1), mesh.corner(t, 2))) / 6;
  }
  return v;
}

}  // namespace radiosity::testing
