// End-to-end tests of `radiosity render`: a solved scene rendered by the program, the picture
// (PNG, PFM or false-colour map) read back and held against the result's own patch values.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include "end_to_end_fixture.h"
#include "pfm_reader.h"
#include "png_reader.h"
#include "render/camera.h"
#include "render/colour_scale.h"
#include "render/false_colour.h"
#include "thermal_scenes.h"

namespace radiosity::testing {
namespace {

// builtin:cornell's ceiling (y = 548.8 mm) and the light in its opening, which shares the
// opening's edges with the ceiling around it.
constexpr double kCeilingY = 548.8;
constexpr double kLightX[2] = {213, 343}, kLightZ[2] = {227, 332};

// A camera under the middle of the ceiling, looking straight up; wide enough to see nearly all
// of the ceiling, so that the brightest ceiling patch is in the picture.
constexpr int kSide = 96;
const std::string kCeilingView =
    " --eye 278,300,279.6 --look-at 278,548.8,279.6 --up 0,0,1 --fov 90 --width 96 --height 96";

// Whether every point of pixel (x, y) images the ceiling outside the light, more than `margin`
// mm from it (a pixel straddling the light's edge mixes both in its subpixel samples).
bool seesCeilingOnly(const render::PinholeCamera& camera, int x, int y, double margin) {
  for (int corner = 0; corner < 4; ++corner) {
    const Vec3 d = camera.direction(x + corner % 2, y + corner / 2, kSide, kSide);
    const Vec3 p = camera.eye + ((kCeilingY - camera.eye.y) / d.y) * d;
    const bool onLight = p.x > kLightX[0] - margin && p.x < kLightX[1] + margin &&
                         p.z > kLightZ[0] - margin && p.z < kLightZ[1] + margin;
    if (onLight || p.x < 0 || p.x > 556 || p.z < 0 || p.z > 559.2) return false;
  }
  return true;
}

// Smooth shading averages B only within one surface, so the ceiling beside the light is a mean
// of ceiling patches: no pixel of it may be brighter than the brightest ceiling patch, drawn
// flat with the same exposure. Averaged with the light across the opening's shared edges (B
// ~100x the ceiling's), it glowed far above that: a star spilling onto the ceiling.
TEST_F(EndToEnd, ALightInACeilingOpeningRendersNoBrighterThanTheCeilingBesideIt) {
  const std::string result = path("c.h5");
  ASSERT_EQ(
      radiosity(1, "solve builtin:cornell --max-area 2000 --rays 64 -q -o " + result).exitCode, 0);
  // Five stops up: the light (the exposure's reference, over 3 % of the picture) saturates,
  // the ceiling lands mid-grey.
  for (const char* shading : {"smooth", "flat"}) {
    const std::string flag = shading == std::string("flat") ? " --flat" : "";
    const ProgramRun run = radiosity(1, "render " + result + kCeilingView + " --exposure 5" + flag +
                                            " -o " + path(std::string(shading) + ".png"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
  }
  const Picture smooth = readPng(path("smooth.png")), flat = readPng(path("flat.png"));
  ASSERT_EQ(smooth.width, kSide);
  ASSERT_EQ(flat.width, kSide);

  render::Camera view;  // kCeilingView's
  view.eye = Vec3{278, 300, 279.6};
  view.lookAt = Vec3{278, kCeilingY, 279.6};
  view.up = {0, 0, 1};
  view.fovDegrees = 90;
  const render::PinholeCamera camera = render::makeCamera(view, {}, {}, 1.0);
  int brightestCeiling = 0;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      if (seesCeilingOnly(camera, x, y, 0.5))
        brightestCeiling = std::max(brightestCeiling, flat.sum(x, y));
  // The bound means something only below saturation.
  ASSERT_GT(brightestCeiling, 0);
  ASSERT_LT(brightestCeiling, 3 * 200);
  // Within 60 mm of the light: its neighbouring patches (max area 2000 mm²). Two levels of
  // slack per channel for the exposure, which the two pictures each set from their own pixels.
  int beside = 0, brightestBeside = 0, atX = -1, atY = -1;
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) {
      if (!seesCeilingOnly(camera, x, y, 0.5) || seesCeilingOnly(camera, x, y, 60)) continue;
      ++beside;
      if (smooth.sum(x, y) > brightestBeside) brightestBeside = smooth.sum(x, y), atX = x, atY = y;
    }
  }
  EXPECT_GT(beside, 100);
  EXPECT_LE(brightestBeside, brightestCeiling + 6) << "at pixel " << atX << ", " << atY;
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Inside builtin:box, looking at the wall z = 1, wide enough that every ray meets a wall.
const std::string kInsideTheBox =
    " --eye 0.5,0.5,0.1 --look-at 0.5,0.5,1 --fov 120 --width 48 --height 32";

// The PFM is the radiance itself: each pixel, smoothly interpolated between patch values, lies
// between the least and the greatest B/π of the result's patches; and the file is the same on
// one rank and on two.
TEST_F(EndToEnd, RenderPfmHoldsTheResultsRadianceOnAnyNumberOfRanks) {
  const std::string result = path("box.h5");
  ASSERT_EQ(radiosity(1, "solve builtin:box --rays 64 -q -o " + result).exitCode, 0);
  for (int ranks : {1, 2}) {
    const ProgramRun run = radiosity(
        ranks, "render " + result + kInsideTheBox + " -o " + path(std::to_string(ranks) + ".pfm"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
  }
  EXPECT_EQ(bytesOf(path("1.pfm")), bytesOf(path("2.pfm")));
  const FloatPicture picture = readPfm(path("2.pfm"));
  EXPECT_EQ(picture.header, "PF\n48 32\n-1.0\n");
  EXPECT_EQ(picture.fileSize, picture.header.size() + 48 * 32 * 3 * 4);

  const Result box = readResult(result);
  double least = 1e300, greatest = 0;
  for (const Rgb& b : box.radiosity)
    for (double c : b) least = std::min(least, c), greatest = std::max(greatest, c);
  ASSERT_GT(least, 0);
  const double pi = std::numbers::pi;
  for (float value : picture.rgb) {
    ASSERT_GE(value, static_cast<float>(least / pi) * (1 - 1e-6f));
    ASSERT_LE(value, static_cast<float>(greatest / pi) * (1 + 1e-6f));
  }
}

// The false-colour map: its legend beside the picture, and the same file on one rank and two.
TEST_F(EndToEnd, RenderFalseColourMapIsTheSameOnAnyNumberOfRanks) {
  const std::string result = path("cornell.h5");
  ASSERT_EQ(
      radiosity(1, "solve builtin:cornell --max-area 4000 --rays 32 -q -o " + result).exitCode, 0);
  for (int ranks : {1, 2}) {
    const ProgramRun run =
        radiosity(ranks, "render " + result + " --width 64 --height 48 --false-colour irradiance" +
                             " -o " + path(std::to_string(ranks) + ".png"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
  }
  EXPECT_EQ(bytesOf(path("1.png")), bytesOf(path("2.png")));
  const Picture map = readPng(path("2.png"));
  const render::LegendLayout legend = render::legendLayout(64, 48);
  EXPECT_EQ(map.width, legend.width);
  EXPECT_EQ(map.height, legend.height);
}

// The position in the colour map whose colour is nearest `colour`.
double mapPosition(const std::array<int, 3>& colour) {
  double best = 0, bestDistance = 1e9;
  for (int i = 0; i <= 1000; ++i) {
    const render::Colour c = render::colourAt(i / 1000.0);
    double distance = 0;
    for (int k = 0; k < 3; ++k) distance += std::abs(c[k] - colour[k]);
    if (distance < bestDistance) bestDistance = distance, best = i / 1000.0;
  }
  return best;
}

// A thermal result's temperature and net flux as maps: the cold ceiling, which the default
// camera sees face on through the floor's back, low on each scale (the coldest surface, and the
// one that gains most), the adiabatic sides around it high. Lighting results have neither, and
// a flux that changes sign takes no log scale: both refused (exit 2).
TEST_F(EndToEnd, RenderMapsAThermalResultsTemperatureAndNetFlux) {
  writeCube(path("box.obj"));
  std::ofstream(path("bc.toml")) << "[surface.\"hot\"]\nemissivity = 0.8\ntemperature = 1000\n"
                                    "[surface.\"cold\"]\nemissivity = 0.5\ntemperature = 300\n"
                                    "[surface.\"sides\"]\nemissivity = 0.3\nheat_flux = 0\n";
  const std::string result = path("box.h5");
  ASSERT_EQ(radiosity(1, "solve " + path("box.obj") + " --thermal " + path("bc.toml") +
                             " --max-area 0.02 -q -o " + result)
                .exitCode,
            0);
  for (const char* quantity : {"temperature", "net_heat_flux"}) {
    const std::string png = path(std::string(quantity) + ".png");
    const ProgramRun run =
        radiosity(1, "render " + result + " --width 64 --height 64 --false-colour " + quantity +
                         " -o " + png);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const Picture map = readPng(png);
    EXPECT_LT(mapPosition(map.at(32, 32)), 0.25) << quantity;  // the ceiling
    EXPECT_GT(mapPosition(map.at(3, 32)), 0.6) << quantity;    // a side
  }
  const std::string lighting = path("light.h5");
  ASSERT_EQ(radiosity(1, "solve builtin:box --rays 16 -q -o " + lighting).exitCode, 0);
  ProgramRun run =
      radiosity(1, "render " + lighting + " --false-colour temperature -o " + path("no.png"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("thermal result's"), std::string::npos) << run.output;
  run = radiosity(
      1, "render " + result + " --false-colour net_heat_flux --scale log -o " + path("no.png"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("changes sign"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(path("no.png")));
}

// An output named neither .png nor .pfm, or an option that does not go with its kind, is refused
// (exit 2) before the result is read (here there is none: reading it would be exit 3), and no
// file is written or changed. (Every such refusal: jobs_test's RenderOutputsAndTheirOptions.)
TEST_F(EndToEnd, RenderRefusesAnOutputItCannotWriteBeforeAnyWork) {
  std::ofstream(path("old.tif")) << "old";
  struct Refused {
    std::string options, says;
  };
  for (const Refused& refused : {
           Refused{"-o " + path("old.tif"), "name it .png"},
           Refused{"-o " + path("x.pfm") + " --false-colour radiosity",
                   "a false-colour map is a PNG"},
       }) {
    const ProgramRun run = radiosity(1, "render " + path("none.h5") + " " + refused.options);
    EXPECT_EQ(run.exitCode, 2) << refused.options << ": " << run.output;
    EXPECT_NE(run.output.find(refused.says), std::string::npos) << run.output;
  }
  EXPECT_EQ(bytesOf(path("old.tif")), "old");
  for (const auto& entry : std::filesystem::directory_iterator(dir_))
    EXPECT_TRUE(entry.path().filename() == "old.tif" || entry.path().filename() == "log.txt")
        << entry.path();
}

}  // namespace
}  // namespace radiosity::testing
