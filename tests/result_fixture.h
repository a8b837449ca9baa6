// What the result-file tests (io_result_*_test.cpp) share: a small bent strip of patches with
// made-up radiosity, irradiance and attributes, dealt to the ranks in blocks, the check that a
// file reads back exactly that, and a fresh directory per test.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity::testing {

/// A 10-triangle strip bent out of plane, so that areas and normals differ between patches.
inline Mesh strip() {
  Mesh mesh;
  for (int i = 0; i < 6; ++i) {
    mesh.vertices.push_back({0.5 * i, 0, 0.1 * i * i});
    mesh.vertices.push_back({0.5 * i, 1.0 + 0.25 * i, 0});
  }
  for (int t = 0; t < 10; ++t) {
    const int64_t i = 2 * (t / 2);
    if (t % 2 == 0)
      mesh.triangles.push_back({i, i + 2, i + 1});
    else
      mesh.triangles.push_back({i + 1, i + 2, i + 3});
    mesh.sourceFace.push_back(t / 2);
    mesh.reflectance.push_back({0.1 * (t % 5), 0.5, 1.0});
    mesh.emission.push_back(t == 3 ? Rgb{10, 20.5, 1e-300} : Rgb{0, 0, 0});
  }
  return mesh;
}

inline std::vector<Rgb> radiosityOf(const Mesh& mesh) {
  std::vector<Rgb> b;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    b.push_back({t + 0.25, 2.0 * t + 1.0 / 3, 1e308});
  return b;
}

inline std::vector<Rgb> irradianceOf(const Mesh& mesh) {
  std::vector<Rgb> h;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) h.push_back({-0.0, 1.0 / (t + 7), 5e-324});
  return h;
}

inline ResultAttributes someAttributes() {
  ResultAttributes a;
  a.ranks = worldSize();
  a.raysPerPatch = 123456789012;
  a.seed = 0xFEDCBA9876543210ull;  // above the int64 range
  a.solver = "gmres";
  a.iterations = 42;
  a.residual = 3.25e-9;
  a.converged = true;
  a.scene = "builtin:cornell?rho=0.5 (größer)";
  a.options = "max-area = 0.01\nrays = 1000\n";
  a.stageSeconds = {{"formfactor", 1.5}, {"solve", 0.125}, {"write", 1e-6}};
  return a;
}

/// The first patch of `rank` when the patches are dealt in contiguous blocks; with
/// `firstRankIdle`, rank 0 of several owns none.
inline int64_t blockStart(int64_t np, int rank, int size, bool firstRankIdle) {
  if (!firstRankIdle || size == 1) return np * rank / size;
  return rank == 0 ? 0 : np * (rank - 1) / (size - 1);
}

struct Owned {
  LocalSolution local;
  std::vector<int32_t> owner;  ///< rank of every patch
};

inline Owned distribute(const Mesh& mesh, bool firstRankIdle = false) {
  const int64_t np = mesh.triangleCount();
  const int rank = worldRank(), size = worldSize();
  Owned o;
  const int64_t first = blockStart(np, rank, size, firstRankIdle);
  const int64_t end = blockStart(np, rank + 1, size, firstRankIdle);
  const std::vector<Rgb> b = radiosityOf(mesh), h = irradianceOf(mesh);
  o.local.firstPatch = first;
  o.local.radiosity.assign(b.begin() + first, b.begin() + end);
  o.local.irradiance.assign(h.begin() + first, h.begin() + end);
  for (int r = 0; r < size; ++r)
    for (int64_t t = blockStart(np, r, size, firstRankIdle);
         t < blockStart(np, r + 1, size, firstRankIdle); ++t)
      o.owner.push_back(r);
  return o;
}

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Each test gets a fresh directory, the same on every rank.
class ResultFileTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_FALSE(dir_.empty()); }

  radiosity::testing::SharedTempDir temp_{"io_result_test"};
  std::filesystem::path dir_ = temp_.path();
};

inline void expectSameAttributes(const ResultAttributes& a, const ResultAttributes& b) {
  EXPECT_EQ(a.formatVersion, b.formatVersion);
  EXPECT_EQ(a.ranks, b.ranks);
  EXPECT_EQ(a.raysPerPatch, b.raysPerPatch);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.solver, b.solver);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.residual, b.residual);
  EXPECT_EQ(a.converged, b.converged);
  EXPECT_EQ(a.scene, b.scene);
  EXPECT_EQ(a.options, b.options);
  EXPECT_EQ(a.stageSeconds, b.stageSeconds);
  EXPECT_EQ(a.history.channel, b.history.channel);
  EXPECT_EQ(a.history.iteration, b.history.iteration);
  EXPECT_EQ(a.history.residual, b.history.residual);
  EXPECT_EQ(a.history.seconds, b.history.seconds);
  EXPECT_EQ(a.solveFigures, b.solveFigures);
  EXPECT_EQ(a.solverChoice, b.solverChoice);
  EXPECT_EQ(a.software, b.software);
}

inline void expectRoundTrip(const std::filesystem::path& path, const Mesh& mesh, const Owned& owned,
                            const ResultAttributes& attributes) {
  const Result r = readResult(path.string());
  EXPECT_EQ(r.mesh.vertices, mesh.vertices);
  EXPECT_EQ(r.mesh.triangles, mesh.triangles);
  EXPECT_EQ(r.mesh.sourceFace, mesh.sourceFace);
  EXPECT_EQ(r.mesh.reflectance, mesh.reflectance);
  EXPECT_EQ(r.mesh.emission, mesh.emission);
  ASSERT_EQ(r.area.size(), mesh.triangles.size());
  ASSERT_EQ(r.normal.size(), mesh.triangles.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_EQ(r.area[t], mesh.area(t)) << "patch " << t;
    EXPECT_EQ(r.normal[t], mesh.normal(t)) << "patch " << t;
  }
  EXPECT_EQ(r.radiosity, radiosityOf(mesh));
  EXPECT_EQ(r.irradiance, irradianceOf(mesh));
  EXPECT_EQ(r.rank, owned.owner);
  expectSameAttributes(r.attributes, attributes);
}

/// A history of three channels, values chosen to need every bit of a double.
inline ResultAttributes attributesWithHistory() {
  ResultAttributes a = someAttributes();
  a.history.channel = {0, 0, 0, 1, 1, 2};
  a.history.iteration = {0, 1, 2, 0, 1, int64_t{1} << 53};
  a.history.residual = {1.0, 1.0 / 3, 5e-324, 0.1, 2.5e-10, 1e308};
  a.history.seconds = {0.0, 1e-6, 0.1 + 0.2, 0.5, 0.75, 12345.678901234567};
  a.solveFigures = {{"setup_seconds", 0.015625}, {"spectral_radius", 0.9 / 7}, {"", -0.0}};
  a.solverChoice = "gmres: ρ max 0.9 > 0.85\nsecond line";
  a.software = {{"radiosity", "0.2.0 (git 1234abc-dirty)"}, {"petsc", "3.18.4"}, {"ü", ""}};
  return a;
}

}  // namespace radiosity::testing
