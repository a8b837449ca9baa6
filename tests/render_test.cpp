// Tests of render/: the PNG it writes, the camera's view, exposure, vertex smoothing, back-face
// culling and failures. Run on one rank (no mpirun needed) or under mpirun -np N.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/corner_radiosity.h"
#include "core/error.h"
#include "core/mesh.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "png_reader.h"
#include "render/camera.h"
#include "render/render.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace radiosity::render {
namespace {

namespace fs = std::filesystem;

using radiosity::testing::Picture;
using radiosity::testing::readPng;
using radiosity::testing::SharedTempDir;
using radiosity::testing::worldRank;

// The walls of the box [0,1]³, in this order, each two triangles facing inwards.
enum Wall { kX0, kX1, kY0, kY1, kZ0, kZ1 };

// A closed box with eight shared vertices, every wall lit from inside with radiosity wallB.
Result makeBox(const std::array<Rgb, 6>& wallB) {
  Result result;
  Mesh& mesh = result.mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  for (int wall = 0; wall < 6; ++wall) {
    int a = wall / 2, side = wall % 2, b = (a + 1) % 3, c = (a + 2) % 3;
    auto vertex = [&](int pb, int pc) -> int64_t { return (side << a) | (pb << b) | (pc << c); };
    std::array<Triangle, 2> quad = {Triangle{vertex(0, 0), vertex(1, 0), vertex(1, 1)},
                                    Triangle{vertex(0, 0), vertex(1, 1), vertex(0, 1)}};
    Vec3 inward{};
    inward[a] = side == 0 ? 1 : -1;
    for (Triangle t : quad) {
      mesh.triangles.push_back(t);
      if (dot(mesh.normal(mesh.triangleCount() - 1), inward) < 0) {
        std::swap(t[1], t[2]);
        mesh.triangles.back() = t;
      }
      mesh.sourceFace.push_back(mesh.triangleCount() - 1);
      mesh.reflectance.push_back({0.5, 0.5, 0.5});
      mesh.emission.push_back({0, 0, 0});
      result.radiosity.push_back(wallB[wall]);
      result.irradiance.push_back({0, 0, 0});
      result.rank.push_back(0);
    }
  }
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    result.area.push_back(mesh.area(t));
    result.normal.push_back(mesh.normal(t));
  }
  return result;
}

Result makeGreyBox(std::array<double, 6> wallB) {
  std::array<Rgb, 6> rgb;
  for (int w = 0; w < 6; ++w) rgb[w] = {wallB[w], wallB[w], wallB[w]};
  return makeBox(rgb);
}

// Renders on every rank of the world; the picture as rank 0 wrote it.
Picture render(const Result& result, const Options& options, const fs::path& path) {
  renderToPng(MPI_COMM_WORLD, result, options, path.string());
  return readPng(path);
}

uint8_t srgbByte(double linear) {
  double display = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::lround(255 * display));
}

Options smallImage(int width = 64, int height = 64) {
  Options options;
  options.width = width;
  options.height = height;
  return options;
}

TEST(Render, WritesValidPngOfRequestedSize) {
  const SharedTempDir dir("render_test");
  fs::path path = dir.path() / "box.png";
  Picture picture = render(makeGreyBox({1, 2, 3, 4, 5, 6}), smallImage(80, 50), path);
  EXPECT_EQ(picture.width, 80);
  EXPECT_EQ(picture.height, 50);
  EXPECT_GT(picture.sum(40, 25), 0);
  // Written atomically: no temporary left beside it.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

TEST(Render, ReplacesAnExistingFile) {
  const SharedTempDir dir("render_test");
  fs::path path = dir.path() / "box.png";
  if (worldRank() == 0) std::ofstream(path) << "old";
  MPI_Barrier(MPI_COMM_WORLD);
  Picture picture = render(makeGreyBox({1, 1, 1, 1, 1, 1}), smallImage(16, 16), path);
  EXPECT_EQ(picture.width, 16);
}

// The front wall (z = 0) faces into the box, away from the default camera: culled, the camera
// sees the back wall through it. Were it not culled, the centre would be black (B = 0).
TEST(Render, BackFacesAreCulled) {
  const SharedTempDir dir("render_test");
  std::array<double, 6> wallB = {1, 1, 1, 1, 0, 1};
  Picture picture = render(makeGreyBox(wallB), smallImage(), dir.path() / "culled.png");
  EXPECT_GT(picture.sum(32, 32), 0);
  // Around the box there is nothing: black background.
  EXPECT_EQ(picture.sum(0, 0), 0);
  EXPECT_EQ(picture.sum(63, 63), 0);
}

// Looking along +z with +y up, the wall at x = 1 is on the left, as in the classic Cornell view
// (red wall left, green wall right).
TEST(Render, DefaultCameraSeesTheClassicView) {
  const SharedTempDir dir("render_test");
  std::array<Rgb, 6> wallB;
  wallB.fill({1, 1, 1});
  wallB[kX1] = {1, 0, 0};
  wallB[kX0] = {0, 1, 0};
  Options options = smallImage();
  options.smooth = false;
  Picture picture = render(makeBox(wallB), options, dir.path() / "cornell.png");
  auto left = picture.at(8, 32), right = picture.at(55, 32), centre = picture.at(32, 32);
  EXPECT_GT(left[0], 0);
  EXPECT_EQ(left[1], 0);
  EXPECT_EQ(right[0], 0);
  EXPECT_GT(right[1], 0);
  EXPECT_EQ(centre[0], centre[1]);
  EXPECT_EQ(centre[1], centre[2]);
}

TEST(Render, DefaultCameraFramesTheCornellBox) {
  Camera camera;
  PinholeCamera pinhole = makeCamera(camera, {0, 0, 0}, {556, 548.8, 559.2}, 1.0);
  // The classic camera sits at (278, 273, −800) with a 39° field of view.
  EXPECT_NEAR(pinhole.eye.x, 278, 1e-9);
  EXPECT_NEAR(pinhole.eye.y, 274.4, 1e-9);
  EXPECT_NEAR(pinhole.eye.z, -800, 20);
  EXPECT_NEAR(pinhole.forward.z, 1, 1e-12);
  EXPECT_NEAR(pinhole.right.x, -1, 1e-12);
  EXPECT_NEAR(pinhole.up.y, 1, 1e-12);
}

TEST(Render, LargerRadiosityRendersBrighter) {
  const SharedTempDir dir("render_test");
  for (bool smooth : {false, true}) {
    Options options = smallImage();
    options.smooth = smooth;
    // Left on screen: x = 1 (B = 1); right: x = 0 (B = 3).
    Picture picture = render(makeGreyBox({3, 1, 2, 2, 2, 2}), options, dir.path() / "walls.png");
    int left = picture.sum(8, 32), right = picture.sum(55, 32);
    EXPECT_GT(left, 0) << "smooth " << smooth;
    EXPECT_GT(right, left) << "smooth " << smooth;
  }
}

// Every visible patch has radiance 1: the 97th percentile is 1 and maps to 0.85, then the
// exposure stops scale it.
TEST(Render, AutomaticExposure) {
  const SharedTempDir dir("render_test");
  const double pi = std::numbers::pi;
  Result box = makeGreyBox({pi, pi, pi, pi, pi, pi});
  for (double stops : {0.0, -1.0, -3.0}) {
    for (bool smooth : {false, true}) {
      Options options = smallImage();
      options.exposureStops = stops;
      options.smooth = smooth;
      Picture picture = render(box, options, dir.path() / "uniform.png");
      uint8_t expected = srgbByte(0.85 * std::exp2(stops));
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(picture.at(32, 32)[c], expected) << "stops " << stops;
        EXPECT_EQ(picture.at(8, 32)[c], expected) << "stops " << stops;
      }
    }
  }
}

TEST(Render, SameImageOnAnyNumberOfRanks) {
  const SharedTempDir dir("render_test");
  Options options = smallImage(40, 30);
  Result box = makeGreyBox({1, 2, 3, 4, 5, 6});
  Picture world = render(box, options, dir.path() / "world.png");
  fs::path alone = dir.path() / ("self" + std::to_string(worldRank()) + ".png");
  renderToPng(MPI_COMM_SELF, box, options, alone.string());
  if (worldRank() == 0) {
    EXPECT_EQ(readPng(alone).rgb, world.rgb);
  }
}

TEST(Render, WriteFailureThrowsAndLeavesNoFile) {
  const SharedTempDir dir("render_test");
  fs::path missing = dir.path() / "no-such-dir" / "box.png";
  try {
    renderToPng(MPI_COMM_WORLD, makeGreyBox({1, 1, 1, 1, 1, 1}), smallImage(8, 8),
                missing.string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_FALSE(fs::exists(missing.parent_path()));

  // The target is a directory: rename fails, and the temporary beside it is removed.
  fs::path directory = dir.path() / "taken";
  if (worldRank() == 0) fs::create_directory(directory);
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_THROW(renderToPng(MPI_COMM_WORLD, makeGreyBox({1, 1, 1, 1, 1, 1}), smallImage(8, 8),
                           directory.string()),
               Error);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);  // only "taken"
}

TEST(Render, RefusesBadOptionsAndResults) {
  const SharedTempDir dir("render_test");
  fs::path path = dir.path() / "bad.png";
  auto exitCodeOf = [&](const Result& result, const Options& options) {
    try {
      renderToPng(MPI_COMM_WORLD, result, options, path.string());
    } catch (const Error& e) {
      return e.exitCode();
    }
    return exit_code::kOk;
  };
  Result box = makeGreyBox({1, 1, 1, 1, 1, 1});
  EXPECT_EQ(exitCodeOf(box, smallImage(0, 8)), exit_code::kUsage);
  Options options = smallImage(8, 8);
  options.camera.up = {0, 0, 1};  // parallel to the default view
  EXPECT_EQ(exitCodeOf(box, options), exit_code::kUsage);
  options = smallImage(8, 8);
  options.camera.eye = Vec3{0.5, 0.5, 0.5};
  options.camera.lookAt = Vec3{0.5, 0.5, 0.5};
  EXPECT_EQ(exitCodeOf(box, options), exit_code::kUsage);
  Result broken = box;
  broken.radiosity.pop_back();
  EXPECT_EQ(exitCodeOf(broken, smallImage(8, 8)), exit_code::kBadInput);
  EXPECT_EQ(exitCodeOf(Result{}, smallImage(8, 8)), exit_code::kBadInput);
  EXPECT_FALSE(fs::exists(path));
}

// A camera inside the box, placed by hand, looking at the back wall.
TEST(Render, ExplicitCameraInsideTheBox) {
  const SharedTempDir dir("render_test");
  std::array<Rgb, 6> wallB;
  wallB.fill({1, 1, 1});
  wallB[kZ1] = {0, 0, 2};
  Options options = smallImage();
  options.camera.eye = Vec3{0.5, 0.5, 0.1};
  options.camera.lookAt = Vec3{0.5, 0.5, 1};
  Picture picture = render(makeBox(wallB), options, dir.path() / "inside.png");
  auto centre = picture.at(32, 32);
  EXPECT_EQ(centre[0], 0);
  EXPECT_GT(centre[2], 0);
  EXPECT_GT(picture.sum(0, 0), 0);  // inside a closed box every ray hits something
}

// Two coplanar triangles of areas 1 and 3 sharing an edge, and a third standing at 90° on it.
TEST(VertexRadiosity, AreaWeightedAverageThatKeepsCreasesSharp) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {3, 3, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 4, 1}};
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  ASSERT_NEAR(area[0], 0.5, 1e-12);
  ASSERT_NEAR(area[1], 2.5, 1e-12);
  ASSERT_NEAR(dot(normal[0], normal[2]), 0, 1e-12);
  std::vector<Rgb> b = {{1, 2, 3}, {4, 5, 6}, {100, 100, 100}};
  CornerRadiosity corner = cornerRadiosity(mesh, normal, area, b, oneSurface(mesh));

  // Vertex 1 and 2 are shared by the coplanar pair: (0.5·B0 + 2.5·B1) / 3.
  for (int c = 0; c < 3; ++c) {
    double mean = (0.5 * b[0][c] + 2.5 * b[1][c]) / 3;
    EXPECT_NEAR(corner[0][1][c], mean, 1e-12);  // vertex 1, seen from patch 0
    EXPECT_NEAR(corner[0][2][c], mean, 1e-12);  // vertex 2
    EXPECT_NEAR(corner[1][0][c], mean, 1e-12);  // vertex 1, seen from patch 1
    EXPECT_NEAR(corner[1][2][c], mean, 1e-12);
    EXPECT_NEAR(corner[0][0][c], b[0][c], 1e-12);  // vertex 0: patch 2 is across the crease
    EXPECT_NEAR(corner[1][1][c], b[1][c], 1e-12);  // vertex 3: patch 1 alone
    // Patch 2 keeps its own value at every corner: its neighbours are all across the crease.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(corner[2][k][c], b[2][c], 1e-12);
  }
}

TEST(VertexRadiosity, DuplicatedVerticesAreWelded) {
  Mesh mesh;
  // The same two triangles as above, but each with its own copy of the shared vertices.
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {3, 3, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
  std::vector<double> area = {mesh.area(0), mesh.area(1)};
  std::vector<Rgb> b = {{1, 1, 1}, {4, 4, 4}};
  CornerRadiosity corner = cornerRadiosity(mesh, normal, area, b, oneSurface(mesh));
  EXPECT_NEAR(corner[0][1][0], (0.5 * 1 + 2.5 * 4) / 3, 1e-12);
  EXPECT_NEAR(corner[1][0][0], (0.5 * 1 + 2.5 * 4) / 3, 1e-12);
}

TEST(VertexRadiosity, NeighboursWithinThirtyDegreesAreAveraged) {
  // Two unit right triangles hinged on the edge (0,0,0)-(0,1,0), folded by 20° and by 40°.
  for (double fold : {20.0, 40.0}) {
    double a = fold * std::numbers::pi / 180;
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {std::cos(a), 0, std::sin(a)}};
    mesh.triangles = {{0, 1, 2}, {0, 3, 1}};
    std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
    ASSERT_NEAR(dot(normal[0], normal[1]), std::cos(a), 1e-12);
    std::vector<double> area = {mesh.area(0), mesh.area(1)};
    CornerRadiosity corner =
        cornerRadiosity(mesh, normal, area, {{{2, 2, 2}}, {{4, 4, 4}}}, oneSurface(mesh));
    EXPECT_NEAR(corner[0][0][0], fold < 30 ? 3 : 2, 1e-12) << fold;
  }
}

// A light in a ceiling opening (builtin:cornell's): the emitting triangle L shares each of its
// edges with a coplanar ceiling triangle (1, 2, 3) of the same reflectance. B jumps at those
// edges, so neither side may be averaged with the other.
//
//          2 ------- 3
//        / | \       |
//      /   |   \  1  |
//    /  2  |  L  \   |
//  4 ----- 0 ------- 1
//          |  3   /
//          |   /
//          | /
//          5
Mesh lightInCeiling() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 2, 4}, {0, 5, 1}};
  mesh.reflectance.assign(4, {0.7, 0.7, 0.7});
  mesh.emission = {{10, 8, 3}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  return mesh;
}

CornerRadiosity cornersOf(const Mesh& mesh, const std::vector<Rgb>& b, const SurfaceIds& surfaces) {
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  return cornerRadiosity(mesh, normal, area, b, surfaces);
}

TEST(VertexRadiosity, ALightNeverMixesWithTheCeilingAroundIt) {
  const Mesh mesh = lightInCeiling();
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    ASSERT_NEAR(mesh.normal(t).z, 1, 1e-15);  // coplanar: only the material tells them apart
  const std::vector<Rgb> b = {{10.35, 8.3, 3.2}, {0.5, 0.4, 0.2}, {0.3, 0.3, 0.1}, {0.1, 0.2, 0.3}};
  const CornerRadiosity corner = cornersOf(mesh, b, materialSurfaces(mesh));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(corner[0][k], b[0]) << "light corner " << k;
  // Every ceiling triangle has area 1/2: each ceiling corner is the plain mean of the ceiling
  // triangles at that vertex, the light left out.
  auto mean = [&](std::vector<int> patches) {
    Rgb m{0, 0, 0};
    for (int s : patches)
      for (int c = 0; c < 3; ++c) m[c] += b[s][c] / static_cast<double>(patches.size());
    return m;
  };
  const std::array<Rgb, 6> atVertex = {mean({2, 3}), mean({1, 3}), mean({1, 2}),
                                       mean({1}),    mean({2}),    mean({3})};
  for (int64_t t = 1; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(corner[t][k][c], atVertex[mesh.triangles[t][k]][c], 1e-15)
            << "ceiling patch " << t << " corner " << k;
}

// Materials are compared by value: another name with the same ρ and E is the same surface, and
// a reflectance alone (a red patch on a white wall) splits one.
TEST(VertexRadiosity, MaterialsAreTheirReflectanceAndEmission) {
  Mesh mesh = lightInCeiling();
  mesh.emission[0] = {0, 0, 0};
  mesh.label = {0, 1, 1, 1};
  mesh.labelNames = {"paint", "ceiling"};
  EXPECT_EQ(materialSurfaces(mesh), (SurfaceIds{0, 0, 0, 0}));
  mesh.reflectance[0] = {0.7, 0.1, 0.1};
  const SurfaceIds red = materialSurfaces(mesh);
  EXPECT_NE(red[0], red[1]);
  EXPECT_EQ(red[1], red[2]);
  EXPECT_EQ(red[1], red[3]);
  const std::vector<Rgb> b(4, Rgb{1, 1, 1});
  std::vector<Rgb> lit = b;
  lit[0] = {5, 1, 1};
  EXPECT_EQ(cornersOf(mesh, lit, red)[1][0], (Rgb{1, 1, 1}));
  // Vertex 1, of patches 0, 1 and 3 (equal areas).
  EXPECT_NEAR(cornersOf(mesh, lit, oneSurface(mesh))[1][0][0], 7.0 / 3, 1e-15);
}

// What the mesh knows beyond materials (a contact line, patches hidden under an object) comes as
// surface ids of the caller's: patch 3, say hidden, is left out of its neighbours' corners.
TEST(VertexRadiosity, SurfaceIdsSplitWhatTheMeshKnows) {
  const Mesh mesh = lightInCeiling();
  const std::vector<Rgb> b = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {0, 0, 0}};
  const CornerRadiosity corner = cornersOf(mesh, b, SurfaceIds{0, 0, 0, 1});
  EXPECT_EQ(corner[0][0], (Rgb{2, 2, 2}));        // vertex 0: patches 0 and 2, not 3
  EXPECT_EQ(corner[0][1], (Rgb{1.5, 1.5, 1.5}));  // vertex 1: patches 0 and 1, not 3
  for (int k = 0; k < 3; ++k) EXPECT_EQ(corner[3][k], b[3]);
  EXPECT_THROW(cornersOf(mesh, b, SurfaceIds{0, 0}), std::invalid_argument);
}

TEST(VertexRadiosity, InterpolatesBarycentrically) {
  std::array<Rgb, 3> corner = {Rgb{1, 0, 0}, Rgb{0, 2, 0}, Rgb{0, 0, 4}};
  Rgb at = interpolate(corner, 0.25, 0.5);
  EXPECT_NEAR(at[0], 0.25, 1e-15);
  EXPECT_NEAR(at[1], 0.5, 1e-15);
  EXPECT_NEAR(at[2], 2, 1e-15);
}

// A linear field's patch means on a 6 × 6 grid of a plane, with a fold of 90° along one side (a
// wall standing on it): the least-squares gradient is the field's own on every patch, the ones
// along the fold and the grid's edge included (where corner averages halve the slope towards
// the edge), and nothing from the wall leaks in across the crease.
TEST(PatchGradients, ExactForALinearFieldUpToTheEdges) {
  Mesh mesh;
  const int n = 6;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.vertices.push_back({double(i), double(j), 0});
  auto at = [&](int i, int j) { return int64_t{j * (n + 1) + i}; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const auto floorPatches = mesh.triangleCount();
  const auto top = static_cast<int64_t>(mesh.vertices.size());
  mesh.vertices.push_back({0, 0, 1});
  mesh.vertices.push_back({double(n), 0, 1});
  mesh.triangles.push_back({at(0, 0), top, at(n, 0)});  // the wall along y = 0, facing +y
  std::vector<Vec3> normal;
  std::vector<Rgb> value;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    const Triangle& c = mesh.triangles[t];
    const Vec3 centroid =
        (1.0 / 3) * (mesh.vertices[c[0]] + mesh.vertices[c[1]] + mesh.vertices[c[2]]);
    // 2x + 3y + 1, and its negative, on the floor; a constant of 100 on the wall
    const double f = 2 * centroid.x + 3 * centroid.y + 1;
    value.push_back(t < floorPatches ? Rgb{f, -f, 0} : Rgb{100, 100, 100});
  }
  ASSERT_NEAR(normal.back().y, 1, 1e-15);
  const PatchGradients g = patchGradients(mesh, normal, value, oneSurface(mesh));
  for (int64_t t = 0; t < floorPatches; ++t) {
    EXPECT_NEAR(g[t][0].x, 2, 1e-12) << t;
    EXPECT_NEAR(g[t][0].y, 3, 1e-12) << t;
    EXPECT_NEAR(g[t][0].z, 0, 1e-12) << t;
    EXPECT_NEAR(g[t][1].y, -3, 1e-12) << t;
    EXPECT_NEAR(length(g[t][2]), 0, 1e-12) << t;
  }
  // The wall is alone in its surface: no direction to fit, no gradient.
  EXPECT_EQ(length(g.back()[0]), 0);
  // A rank fits only its own rows: each the same, bit for bit, as in the whole scene's fit; a
  // range beyond the patches is refused.
  const int64_t first = 5, last = 29;
  const PatchGradients part = patchGradients(mesh, normal, value, oneSurface(mesh), first, last);
  ASSERT_EQ(static_cast<int64_t>(part.size()), last - first);
  for (int64_t t = first; t < last; ++t)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(part[t - first][c].x, g[t][c].x) << t;
      EXPECT_EQ(part[t - first][c].y, g[t][c].y) << t;
      EXPECT_EQ(part[t - first][c].z, g[t][c].z) << t;
    }
  EXPECT_THROW(patchGradients(mesh, normal, value, oneSurface(mesh), 3, mesh.triangleCount() + 1),
               std::invalid_argument);
  // Without an array of normals the fit takes the mesh's (what the discretisation estimate does,
  // to hold no scene-wide array of them): the same gradients, bit for bit.
  const SurfaceIds surfaces = oneSurface(mesh);
  const GradientFit fromMesh(mesh, surfaces);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::array<Vec3, 3> h = fromMesh(t, value);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(h[c].x, g[t][c].x) << t;
      EXPECT_EQ(h[c].y, g[t][c].y) << t;
      EXPECT_EQ(h[c].z, g[t][c].z) << t;
    }
  }
}

// A rank fits its own rows from its own values and its neighbours' alone: a fit of patches
// [first, last), given the values of those patches and of neighboursOutside(), equals the whole
// scene's fit bit for bit; the neighbours are exactly the patches outside sharing a corner's
// position, and a patch outside the range, or a value not held, is refused.
TEST(PatchGradients, AFitOfARangeNeedsOnlyItsNeighbours) {
  Mesh mesh;
  testing::addSubdividedQuad(mesh, {0, 0, 0}, {8, 0, 0}, {0, 5.6, 0}, 8, {0.5, 0.5, 0.5},
                             {0, 0, 0});
  std::vector<Rgb> value;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const Triangle& c = mesh.triangles[t];
    const Vec3 centroid =
        (1.0 / 3) * (mesh.vertices[c[0]] + mesh.vertices[c[1]] + mesh.vertices[c[2]]);
    value.push_back({std::sin(centroid.x) * centroid.y, centroid.x * centroid.x, 1.0 / (1 + t)});
  }
  const SurfaceIds surfaces = oneSurface(mesh);
  const GradientFit whole(mesh, surfaces);
  const int64_t first = 37, last = 81;
  const GradientFit part(mesh, surfaces, first, last);
  const std::vector<int64_t> around = part.neighboursOutside(first, last);
  std::vector<int64_t> expected;
  for (int64_t s = 0; s < mesh.triangleCount(); ++s) {
    if (s >= first && s < last) continue;
    bool touches = false;
    for (int64_t t = first; t < last && !touches; ++t)
      for (int64_t a : mesh.triangles[s])
        for (int64_t b : mesh.triangles[t]) touches |= a == b;
    if (touches) expected.push_back(s);
  }
  EXPECT_EQ(around, expected);
  const std::vector<Rgb> block(value.begin() + first, value.begin() + last);
  std::vector<Rgb> aroundValues;
  for (int64_t s : around) aroundValues.push_back(value[s]);
  const PatchValues held(first, block, around, aroundValues);
  for (int64_t t = first; t < last; ++t) {
    const std::array<Vec3, 3> g = part(t, held), h = whole(t, value);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(g[c].x, h[c].x) << t;
      EXPECT_EQ(g[c].y, h[c].y) << t;
      EXPECT_EQ(g[c].z, h[c].z) << t;
    }
  }
  EXPECT_THROW(part(first - 1, held), std::out_of_range);
  const PatchValues lacking(first, block, {}, {});
  EXPECT_THROW(part(first, lacking), std::out_of_range);
  EXPECT_THROW(GradientFit(mesh, surfaces, 5, mesh.triangleCount() + 1), std::invalid_argument);
}

TEST(PatchGradients, KeepSurfacesApart) {
  // Two coplanar triangles of different surfaces: each alone, so no gradient across the edge.
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  const std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
  const PatchGradients g =
      patchGradients(mesh, normal, {{{0, 0, 0}}, {{5, 5, 5}}}, SurfaceIds{0, 1});
  EXPECT_EQ(length(g[0][0]), 0);
  EXPECT_EQ(length(g[1][0]), 0);
  const PatchGradients joined = patchGradients(mesh, normal, {{{0, 0, 0}}, {{5, 5, 5}}}, {0, 0});
  EXPECT_GT(length(joined[0][0]), 0);
}

}  // namespace
}  // namespace radiosity::render
