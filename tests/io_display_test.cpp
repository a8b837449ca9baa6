// The display mesh (smooth radiosity as point data, split at creases) and its tone-mapped
// luminance, on any number of ranks: what ParaView shows must be what the renderer shows.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/corner_radiosity.h"
#include "core/error.h"
#include "io/store/display_writer.h"
#include "io/store/hdf5_read.h"
#include "result_datasets.h"
#include "result_fixture.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
namespace fs = std::filesystem;
using testing::distribute;
using testing::Owned;
using testing::readAll;
using testing::ResultFileTest;
using testing::someAttributes;
using testing::strip;

// Two triangles sharing the edge (0,1): in the plane z = 0 or, with `folded`, the second one
// turned up to the plane x = 0 (a 90° crease).
Mesh hinge(bool folded) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, folded ? Vec3{0, 0, 1} : Vec3{-1, 0, 0}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}};
  mesh.reflectance.assign(2, {0.5, 0.5, 0.5});
  mesh.emission.assign(2, {0, 0, 0});
  return mesh;
}

DisplayMesh displayOf(const Mesh& mesh, const std::vector<Rgb>& b) {
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  return displayMesh(mesh, cornerRadiosity(mesh, normal, area, b, materialSurfaces(mesh)));
}

TEST(DisplayMesh, OneSurfaceSharesItsVerticesAndAveragesThem) {
  const DisplayMesh d = displayOf(hinge(false), {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 4u);  // the shared edge's two vertices stay shared
  const Triangle &a = d.triangles[0], &b = d.triangles[1];
  EXPECT_EQ(a[0], b[0]);
  EXPECT_EQ(a[2], b[1]);
  EXPECT_EQ(d.radiosity[a[0]], (Rgb{2, 2, 2}));  // equal areas: the plain mean
  EXPECT_EQ(d.radiosity[a[1]], (Rgb{1, 1, 1}));  // a corner of the first triangle only
  EXPECT_EQ(d.radiosity[b[2]], (Rgb{3, 3, 3}));
}

TEST(DisplayMesh, ACreaseSplitsItsVertices) {
  const Mesh mesh = hinge(true);
  const DisplayMesh d = displayOf(mesh, {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 6u);
  for (int64_t t = 0; t < 2; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int64_t v = d.triangles[t][k];
      EXPECT_EQ(d.radiosity[v], (t == 0 ? Rgb{1, 1, 1} : Rgb{3, 3, 3}));  // no averaging across
      const Vec3 &p = d.vertices[v], &q = mesh.vertices[mesh.triangles[t][k]];
      EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z);
    }
  }
}

// A light and the ceiling around it, coplanar and sharing an edge: B jumps there, and ParaView
// must not smooth it away any more than the renderer does.
TEST(DisplayMesh, AChangeOfMaterialSplitsItsVertices) {
  Mesh mesh = hinge(false);
  mesh.emission[1] = {2, 2, 2};
  const DisplayMesh d = displayOf(mesh, {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 6u);
  for (int64_t t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(d.radiosity[d.triangles[t][k]], (t == 0 ? Rgb{1, 1, 1} : Rgb{3, 3, 3}));
}

TEST(DisplayMesh, RadiosityNearTheLargestDoubleStaysFinite) {
  const DisplayMesh d = displayOf(hinge(false), {{1e308, 1, 1}, {1.5e308, 1, 1}});
  for (const Rgb& b : d.radiosity) EXPECT_TRUE(std::isfinite(b[0]) && b[0] >= 1e308) << b[0];
}
// The luminance /display/luminance_tonemapped shows as 0.5, as docs/result-format.md defines it:
// the area-weighted geometric mean of the luminance of the patches that reflect and do not emit,
// Σ A log Y summed a display chunk at a time and the chunks' sums in order.
double expectedMidpoint(const Mesh& mesh, const std::vector<Rgb>& b) {
  const int64_t np = mesh.triangleCount();
  double logSum = 0, area = 0;
  for (int64_t from = 0; from < np; from += kDisplayChunk) {
    double chunkLog = 0, chunkArea = 0;
    for (int64_t p = from; p < std::min(np, from + kDisplayChunk); ++p) {
      const double y = luminance(b[p]);
      const Rgb& rho = mesh.reflectance[p];
      if (y > 0 && mesh.emission[p] == Rgb{0, 0, 0} && std::max({rho[0], rho[1], rho[2]}) > 0) {
        chunkLog += mesh.area(p) * std::log(y);
        chunkArea += mesh.area(p);
      }
    }
    logSum += chunkLog;
    area += chunkArea;
  }
  return std::exp(logSum / area);
}

double midpointIn(const fs::path& file) {
  h5::Handle handle = h5::openFile(file.string(), "result file");
  const h5::Handle dataset =
      h5::own(H5Dopen2(handle.get(), "/display/luminance_tonemapped", H5P_DEFAULT), "H5Dopen2");
  return h5::readAttribute<double>(dataset.get(), file.string(), "midpoint");
}

// The file's display mesh is the renderer's corner radiosity, whatever the ranks' blocks.
TEST_F(ResultFileTest, DisplayMeshIsTheRenderersCornerRadiosity) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());
  const DisplayMesh expected = displayOf(mesh, testing::radiosityOf(mesh));
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto vertices = readAll<double>(path, "/display/vertices");
  const auto radiosity = readAll<double>(path, "/display/radiosity");
  ASSERT_EQ(triangles.size(), 3 * static_cast<size_t>(mesh.triangleCount()));
  ASSERT_EQ(vertices.size(), 3 * expected.vertices.size());
  ASSERT_EQ(radiosity.size(), 3 * expected.vertices.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<size_t>(triangles[3 * t + k]);
      const Vec3& p = mesh.vertices[mesh.triangles[t][k]];
      EXPECT_EQ(vertices[3 * v], p.x);
      EXPECT_EQ(vertices[3 * v + 1], p.y);
      EXPECT_EQ(vertices[3 * v + 2], p.z);
      const Rgb& b = expected.radiosity[expected.triangles[t][k]];
      for (int c = 0; c < 3; ++c) EXPECT_EQ(radiosity[3 * v + c], b[c]) << t << " " << k;
    }
  }
}

// A scene of more patches than a display chunk: the file holds each chunk's display mesh, one
// after the other (its vertices shared inside the chunk), whatever the ranks' blocks; every
// corner shows the whole scene's corner radiosity at its own position.
TEST_F(ResultFileTest, DisplayMeshOfAScenePastAChunkIsTheSameOnAnyRanks) {
  Mesh mesh;
  const int n = 190;  // 2 n² = 72,200 patches: a chunk of 65,536 and part of another
  testing::addSubdividedQuad(mesh, {0, 0, 0}, {double(n), 0, 0}, {0, double(n), 0}, n,
                             {0.5, 0.5, 0.5}, {0, 0, 0});
  const int64_t np = mesh.triangleCount();
  ASSERT_GT(np, kDisplayChunk);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());

  const std::vector<Rgb> b = testing::radiosityOf(mesh);
  const DisplayMesh whole = displayOf(mesh, b);
  const SurfaceIds surfaces = materialSurfaces(mesh);
  const CornerAverages corners(mesh, surfaces, 0, np);
  std::vector<double> expectedVertices, expectedRadiosity;
  std::vector<int64_t> expectedTriangles;
  for (int64_t from = 0; from < np; from += kDisplayChunk) {
    const DisplayMesh chunk = corners.displayMesh(b, from, std::min(np, from + kDisplayChunk));
    const auto shift = static_cast<int64_t>(expectedVertices.size() / 3);
    for (const Triangle& t : chunk.triangles)
      for (int64_t v : t) expectedTriangles.push_back(v + shift);
    for (size_t v = 0; v < chunk.vertices.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        expectedVertices.push_back(c == 0   ? chunk.vertices[v].x
                                   : c == 1 ? chunk.vertices[v].y
                                            : chunk.vertices[v].z);
        expectedRadiosity.push_back(chunk.radiosity[v][c]);
      }
  }
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto vertices = readAll<double>(path, "/display/vertices");
  const auto radiosity = readAll<double>(path, "/display/radiosity");
  EXPECT_EQ(triangles, expectedTriangles);
  EXPECT_EQ(vertices, expectedVertices);
  EXPECT_EQ(radiosity, expectedRadiosity);
  // The tone-mapped luminance, its midpoint summed a chunk at a time: the same bits on any ranks.
  const double midpoint = expectedMidpoint(mesh, b);
  EXPECT_EQ(midpointIn(path), midpoint);
  const auto tonemapped = readAll<double>(path, "/display/luminance_tonemapped", 0);
  ASSERT_EQ(3 * tonemapped.size(), expectedRadiosity.size());
  for (size_t v = 0; v < tonemapped.size(); ++v) {
    const double y = luminance(
        Rgb{expectedRadiosity[3 * v], expectedRadiosity[3 * v + 1], expectedRadiosity[3 * v + 2]});
    ASSERT_EQ(tonemapped[v], y / (y + midpoint)) << v;
  }
  // Only the chunks' shared border repeats vertices: here one row of the grid, 0.5 %.
  EXPECT_GT(vertices.size(), 3 * whole.vertices.size());
  EXPECT_LT(vertices.size(), 3 * whole.vertices.size() * 1.01);
  for (int64_t t = 0; t < np; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<size_t>(triangles[3 * t + k]);
      const Vec3& p = mesh.vertices[mesh.triangles[t][k]];
      ASSERT_EQ(vertices[3 * v], p.x) << t;
      ASSERT_EQ(vertices[3 * v + 1], p.y) << t;
      const Rgb& expected = whole.radiosity[whole.triangles[t][k]];
      for (int c = 0; c < 3; ++c) ASSERT_EQ(radiosity[3 * v + c], expected[c]) << t << " " << k;
    }
}

// The walls at one luminance show as 0.5 (the midpoint is theirs), a light brighter: what a
// colour map spreads over its range, where a linear one leaves the walls in its bottom corner.
TEST_F(ResultFileTest, TonemappedLuminanceShowsTheWallsMidScale) {
  const Mesh mesh = strip();  // patch 3 emits
  Owned owned = distribute(mesh);
  for (size_t k = 0; k < owned.local.radiosity.size(); ++k)
    owned.local.radiosity[k] = owned.local.firstPatch + static_cast<int64_t>(k) == 3
                                   ? Rgb{60, 50, 40}
                                   : Rgb{0.5, 0.5, 0.5};
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  EXPECT_NEAR(midpointIn(path), 0.5, 1e-15);
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto tonemapped = readAll<double>(path, "/display/luminance_tonemapped", 0);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const double shown = tonemapped[static_cast<size_t>(triangles[3 * t + k])];
      if (t == 3)  // the light's corners, apart from the walls' (another material)
        EXPECT_NEAR(shown, 51.404 / 51.904, 1e-12) << t;  // Y = 0.2126·60 + 0.7152·50 + 0.0722·40
      else
        EXPECT_NEAR(shown, 0.5, 1e-15) << t;
    }
  }
}

}  // namespace
}  // namespace radiosity
