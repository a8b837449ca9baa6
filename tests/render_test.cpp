// Tests of render/: the PNG picture it writes, the camera's view, exposure, back-face culling and
// failures (its PFM and false-colour map: render_outputs_test.cpp; the corner radiosity it smooths
// with: corner_radiosity_test.cpp). Run on one rank (no mpirun needed) or under mpirun -np N.
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

#include "core/error.h"
#include "core/mesh.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "png_reader.h"
#include "render/camera.h"
#include "render/render.h"
#include "render_box.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace radiosity::render {
namespace {

namespace fs = std::filesystem;

using radiosity::testing::kX0;
using radiosity::testing::kX1;
using radiosity::testing::kZ1;
using radiosity::testing::makeBox;
using radiosity::testing::makeGreyBox;
using radiosity::testing::Picture;
using radiosity::testing::readPng;
using radiosity::testing::SharedTempDir;
using radiosity::testing::worldRank;

// Renders on every rank of the world; the picture as rank 0 wrote it.
Picture render(const Result& result, const Options& options, const fs::path& path) {
  renderImage(MPI_COMM_WORLD, result, options, path.string());
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
  renderImage(MPI_COMM_SELF, box, options, alone.string());
  if (worldRank() == 0) {
    EXPECT_EQ(readPng(alone).rgb, world.rgb);
  }
}

TEST(Render, WriteFailureThrowsAndLeavesNoFile) {
  const SharedTempDir dir("render_test");
  fs::path missing = dir.path() / "no-such-dir" / "box.png";
  try {
    renderImage(MPI_COMM_WORLD, makeGreyBox({1, 1, 1, 1, 1, 1}), smallImage(8, 8),
                missing.string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_FALSE(fs::exists(missing.parent_path()));

  // The target is a directory: rename fails, and the temporary beside it is removed.
  fs::path directory = dir.path() / "taken.png";
  if (worldRank() == 0) fs::create_directory(directory);
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_THROW(renderImage(MPI_COMM_WORLD, makeGreyBox({1, 1, 1, 1, 1, 1}), smallImage(8, 8),
                           directory.string()),
               Error);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);  // only "taken.png"
}

TEST(Render, RefusesBadOptionsAndResults) {
  const SharedTempDir dir("render_test");
  fs::path path = dir.path() / "bad.png";
  auto exitCodeOf = [&](const Result& result, const Options& options) {
    try {
      renderImage(MPI_COMM_WORLD, result, options, path.string());
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

}  // namespace
}  // namespace radiosity::render
