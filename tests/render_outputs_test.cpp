// Tests of render/'s other outputs: the linear HDR PFM (the radiance itself, exactly, rows bottom
// to top), the false-colour map with its legend and scale, and the output's name choosing the
// format. Run on one rank (no mpirun needed) or under mpirun -np N.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "pfm_reader.h"
#include "png_reader.h"
#include "render/bitmap_font.h"
#include "render/colour_scale.h"
#include "render/false_colour.h"
#include "render/render.h"
#include "render_box.h"
#include "temp_dir.h"

namespace radiosity::render {
namespace {

namespace fs = std::filesystem;
using namespace radiosity::testing;

constexpr double kPi = std::numbers::pi;

Options smallImage(int width = 64, int height = 64) {
  Options options;
  options.width = width;
  options.height = height;
  return options;
}

// A camera inside the box looking at the back wall (z = 1), wide enough to see the floor at the
// bottom of the picture and the ceiling at its top: every ray hits a wall.
Options insideTheBox(int width, int height, double fov = 120) {
  Options options = smallImage(width, height);
  options.camera.eye = Vec3{0.5, 0.5, 0.1};
  options.camera.lookAt = Vec3{0.5, 0.5, 1};
  options.camera.fovDegrees = fov;
  return options;
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

int exitCodeOf(const Result& result, const Options& options, const fs::path& path) {
  try {
    renderImage(MPI_COMM_WORLD, result, options, path.string());
  } catch (const Error& e) {
    return e.exitCode();
  }
  return exit_code::kOk;
}

// --- The PFM ----------------------------------------------------------------------------------

// A uniform box seen from inside: every pixel is B/π, in float, per channel: flat patches give
// exactly the float nearest B/π (the subpixel samples are equal and their mean is exact);
// smoothing averages equal corner values, within a float's rounding.
TEST(RenderPfm, HoldsTheRadianceOfEveryPixel) {
  const SharedTempDir dir("render_outputs_test");
  const Rgb b = {1.5, 30, 4e5};
  std::array<Rgb, 6> wallB;
  wallB.fill(b);
  for (bool smooth : {false, true}) {
    Options options = insideTheBox(40, 30);
    options.smooth = smooth;
    const fs::path path = dir.path() / "box.pfm";
    renderImage(MPI_COMM_WORLD, makeBox(wallB), options, path.string());
    const FloatPicture picture = readPfm(path);
    EXPECT_EQ(picture.header, "PF\n40 30\n-1.0\n");
    EXPECT_EQ(picture.fileSize, picture.header.size() + 40 * 30 * 3 * sizeof(float));
    ASSERT_EQ(picture.rgb.size(), 40u * 30 * 3);
    for (int y = 0; y < 30; ++y) {
      for (int x = 0; x < 40; ++x) {
        for (int c = 0; c < 3; ++c) {
          const float expected = static_cast<float>(b[c] / kPi);
          if (smooth)
            ASSERT_FLOAT_EQ(picture.at(x, y)[c], expected) << x << ", " << y << " channel " << c;
          else
            ASSERT_EQ(picture.at(x, y)[c], expected) << x << ", " << y << " channel " << c;
        }
      }
    }
  }
}

// The file's first row is the picture's bottom: the floor, not the ceiling. No exposure: the
// values are the radiance however bright.
TEST(RenderPfm, RowsRunBottomToTopUnexposed) {
  const SharedTempDir dir("render_outputs_test");
  std::array<double, 6> wallB = {1, 1, 1, 1, 1, 1};
  wallB[kY0] = 1e-3;  // floor
  wallB[kY1] = 1e6;   // ceiling
  Options options = insideTheBox(32, 32);
  options.smooth = false;
  const fs::path path = dir.path() / "rows.pfm";
  renderImage(MPI_COMM_WORLD, makeGreyBox(wallB), options, path.string());
  const FloatPicture picture = readPfm(path);
  ASSERT_EQ(picture.height, 32);
  EXPECT_EQ(picture.at(16, 0)[1], static_cast<float>(1e6 / kPi));    // top: the ceiling
  EXPECT_EQ(picture.at(16, 31)[1], static_cast<float>(1e-3 / kPi));  // bottom: the floor
  EXPECT_EQ(picture.at(16, 16)[1], static_cast<float>(1 / kPi));     // the back wall
}

// A PFM that cannot be written fails on every rank (exit 1, naming the file) and leaves nothing:
// no file in a missing folder, and no temporary beside a folder of the output's name.
TEST(RenderPfm, WriteFailureLeavesNoFile) {
  const SharedTempDir dir("render_outputs_test");
  const Result box = makeGreyBox({1, 1, 1, 1, 1, 1});
  const fs::path missing = dir.path() / "no-such-dir" / "box.pfm";
  try {
    renderImage(MPI_COMM_WORLD, box, smallImage(8, 8), missing.string());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing.parent_path()));
  const fs::path taken = dir.path() / "taken.pfm";
  if (worldRank() == 0) fs::create_directory(taken);
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(exitCodeOf(box, smallImage(8, 8), taken), exit_code::kFailure);
  EXPECT_EQ(namesIn(dir.path()), std::set<std::string>{"taken.pfm"});
}

// Rows are shared among the ranks and summed: the same bytes on any number of ranks, for each
// kind of output.
TEST(RenderOutputs, SameFileOnAnyNumberOfRanks) {
  const SharedTempDir dir("render_outputs_test");
  const Result box =
      makeBox({Rgb{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {1, 10, 100}, {0, 0, 0}, {5, 5, 5}},
              {Rgb{3, 2, 1}, {6, 5, 4}, {9, 8, 7}, {1, 1, 1}, {2, 2, 2}, {0, 1, 0}});
  for (FalseColour falseColour :
       {FalseColour::kNone, FalseColour::kRadiosity, FalseColour::kIrradiance}) {
    for (const std::string extension : {".pfm", ".png"}) {
      if (extension == ".pfm" && falseColour != FalseColour::kNone) continue;
      Options options = smallImage(40, 30);
      options.falseColour = falseColour;
      const fs::path world = dir.path() / ("world" + extension);
      renderImage(MPI_COMM_WORLD, box, options, world.string());
      const fs::path alone = dir.path() / ("self" + std::to_string(worldRank()) + extension);
      renderImage(MPI_COMM_SELF, box, options, alone.string());
      EXPECT_EQ(bytesOf(alone), bytesOf(world))
          << extension << " " << nameIn(kFalseColourNames, falseColour, "picture");
      MPI_Barrier(MPI_COMM_WORLD);  // every rank has read `world` before it is written again
    }
  }
}

// --- The format by name -----------------------------------------------------------------------

TEST(RenderOutputs, TheExtensionNamesTheFormat) {
  EXPECT_EQ(imageFormatOf("a/b.png"), ImageFormat::kPng);
  EXPECT_EQ(imageFormatOf("B.PNG"), ImageFormat::kPng);
  EXPECT_EQ(imageFormatOf("hdr.pfm"), ImageFormat::kPfm);
  EXPECT_EQ(imageFormatOf("hdr.Pfm"), ImageFormat::kPfm);
  for (const std::string name : {"box.tif", "box.exr", "box", "png", "box.png.tmp", ".pfm/x"}) {
    try {
      imageFormatOf(name);
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.exitCode(), exit_code::kUsage) << name;
      const std::string message = e.what();
      EXPECT_NE(message.find(".png"), std::string::npos) << message;
      EXPECT_NE(message.find(".pfm"), std::string::npos) << message;
    }
  }
}

// An unknown extension, a false-colour PFM or an exposure with nothing to expose: refused (exit
// 2) before any work, no file left and an existing one unchanged.
TEST(RenderOutputs, RefusesWhatItCannotWrite) {
  const SharedTempDir dir("render_outputs_test");
  const Result box = makeGreyBox({1, 1, 1, 1, 1, 1});
  for (const std::string name : {"box.tif", "box"})
    EXPECT_EQ(exitCodeOf(box, smallImage(8, 8), dir.path() / name), exit_code::kUsage) << name;
  Options map = smallImage(8, 8);
  map.falseColour = FalseColour::kRadiosity;
  EXPECT_EQ(exitCodeOf(box, map, dir.path() / "map.pfm"), exit_code::kUsage);
  Options exposed = smallImage(8, 8);
  exposed.exposureStops = 1;
  EXPECT_EQ(exitCodeOf(box, exposed, dir.path() / "hdr.pfm"), exit_code::kUsage);
  map.exposureStops = 1;
  EXPECT_EQ(exitCodeOf(box, map, dir.path() / "map.png"), exit_code::kUsage);
  EXPECT_TRUE(namesIn(dir.path()).empty());
  MPI_Barrier(MPI_COMM_WORLD);  // every rank has looked before rank 0 writes

  const fs::path kept = dir.path() / "kept.pfm";
  if (worldRank() == 0) writeText(kept, "old");
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(exitCodeOf(box, exposed, kept), exit_code::kUsage);
  EXPECT_EQ(bytesOf(kept), "old");
  EXPECT_EQ(namesIn(dir.path()), std::set<std::string>{"kept.pfm"});
}

// A map of H needs H for every patch.
TEST(RenderOutputs, IrradianceMapNeedsTheIrradiance) {
  const SharedTempDir dir("render_outputs_test");
  Result box = makeGreyBox({1, 1, 1, 1, 1, 1});
  box.irradiance.pop_back();
  Options map = smallImage(8, 8);
  map.falseColour = FalseColour::kIrradiance;
  EXPECT_EQ(exitCodeOf(box, map, dir.path() / "h.png"), exit_code::kBadInput);
  map.falseColour = FalseColour::kRadiosity;
  EXPECT_EQ(exitCodeOf(box, map, dir.path() / "b.png"), exit_code::kOk);
}

// --- The false-colour map ---------------------------------------------------------------------

// The luminance of a grey value as the renderer computes it from float pixels.
double greyLuminance(double value) {
  const float v = static_cast<float>(value);
  return 0.2126 * v + 0.7152 * v + 0.0722 * v;
}

// Every picture pixel's colour, as a set.
std::set<std::array<int, 3>> pictureColours(const Picture& map, int width, int height) {
  std::set<std::array<int, 3>> colours;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) colours.insert(map.at(x, y));
  return colours;
}

// Seen from inside, a box of uniform B is one colour in B's map whatever H does, and one of
// uniform H is one colour in H's map whatever B does: each map shows its own quantity.
TEST(FalseColour, AUniformQuantityIsOneColour) {
  const SharedTempDir dir("render_outputs_test");
  const std::array<Rgb, 6> uniform = {Rgb{2, 2, 2}, {2, 2, 2}, {2, 2, 2},
                                      {2, 2, 2},    {2, 2, 2}, {2, 2, 2}};
  const std::array<Rgb, 6> varied = {Rgb{1, 1, 1}, {2, 2, 2}, {3, 3, 3},
                                     {4, 4, 4},    {5, 5, 5}, {6, 6, 6}};
  struct Case {
    FalseColour shown;
    Result box;
  };
  for (const Case& c : {Case{FalseColour::kRadiosity, makeBox(uniform, varied)},
                        Case{FalseColour::kIrradiance, makeBox(varied, uniform)}}) {
    for (bool smooth : {false, true}) {
      Options options = insideTheBox(48, 40);
      options.falseColour = c.shown;
      options.smooth = smooth;
      const fs::path path = dir.path() / "uniform.png";
      renderImage(MPI_COMM_WORLD, c.box, options, path.string());
      const Picture map = readPng(path);
      const ColourScale scale = chooseScale(greyLuminance(2), greyLuminance(2), Scale::kAuto);
      const Colour expected = colourAt(scale.position(greyLuminance(2)));
      EXPECT_EQ(pictureColours(map, 48, 40),
                (std::set<std::array<int, 3>>{{expected[0], expected[1], expected[2]}}))
          << nameIn(kFalseColourNames, c.shown) << " smooth " << smooth;

      // The other quantity, varied, is not one colour.
      options.falseColour =
          c.shown == FalseColour::kRadiosity ? FalseColour::kIrradiance : FalseColour::kRadiosity;
      renderImage(MPI_COMM_WORLD, c.box, options, path.string());
      EXPECT_GT(pictureColours(readPng(path), 48, 40).size(), 3u);
    }
  }
}

// The position in the colour map whose colour is nearest `colour`.
double positionOf(const std::array<int, 3>& colour) {
  double best = -1, bestDistance = 1e9;
  for (int i = 0; i <= 1000; ++i) {
    const Colour candidate = colourAt(i / 1000.0);
    double distance = 0;
    for (int c = 0; c < 3; ++c) distance += std::pow(candidate[c] - colour[c], 2);
    if (distance < bestDistance) bestDistance = distance, best = i / 1000.0;
  }
  return best;
}

// The relative luminance of an sRGB colour (0 black, 1 white).
double relativeLuminance(const std::array<int, 3>& colour) {
  double linear[3];
  for (int c = 0; c < 3; ++c) {
    const double v = colour[c] / 255.0;
    linear[c] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  }
  return 0.2126 * linear[0] + 0.7152 * linear[1] + 0.0722 * linear[2];
}

// The legend sits to the picture's right: text above a colour bar that climbs steadily through
// the colour map from its bottom to its top, ticks beside it and their labels.
TEST(FalseColour, LegendBarRunsThroughTheColourMap) {
  const SharedTempDir dir("render_outputs_test");
  for (int height : {48, 400}) {  // the small text, and the text drawn twice as big
    Options options = smallImage(64, height);
    options.falseColour = FalseColour::kRadiosity;
    const fs::path path = dir.path() / "legend.png";
    renderImage(MPI_COMM_WORLD, makeGreyBox({1, 2, 3, 4, 5, 6}), options, path.string());
    const Picture map = readPng(path);
    const LegendLayout at = legendLayout(64, height);
    ASSERT_EQ(map.width, at.width);
    ASSERT_EQ(map.height, at.height);
    ASSERT_GE(at.height, height);
    ASSERT_GT(at.barX, 64);
    ASSERT_GE(at.barHeight, 64);

    double previous = -1;
    const int x = at.barX + at.barWidth / 2;
    for (int row = at.barY + at.barHeight - 1; row >= at.barY; --row) {
      // (a level of rounding in the bytes may put a row's nearest position a little back)
      const double t = positionOf(map.at(x, row));
      ASSERT_GE(t, previous - 0.01) << "bar row " << row;
      previous = std::max(previous, t);
    }
    EXPECT_LE(positionOf(map.at(x, at.barY + at.barHeight - 1)), 0.01);
    EXPECT_GE(positionOf(map.at(x, at.barY)), 0.99);
    // And, whatever the map, its lightness rises steadily from a dark bottom to a bright top.
    double lighter = 0;
    for (int row = at.barY + at.barHeight - 1; row >= at.barY; --row) {
      const double y = relativeLuminance(map.at(x, row));
      ASSERT_GE(y, lighter - 1e-3) << "bar row " << row;
      lighter = std::max(lighter, y);
    }
    EXPECT_LT(relativeLuminance(map.at(x, at.barY + at.barHeight - 1)), 0.05);
    EXPECT_GT(relativeLuminance(map.at(x, at.barY)), 0.7);

    // Ink: the text above the bar, the ticks and labels right of it; none left of the bar.
    auto inkIn = [&](int x0, int y0, int x1, int y1) {
      int pixels = 0;
      for (int y = y0; y < y1; ++y)
        for (int xx = x0; xx < x1; ++xx)
          if (map.at(xx, y) == std::array<int, 3>{kInk[0], kInk[1], kInk[2]}) ++pixels;
      return pixels;
    };
    EXPECT_GT(inkIn(at.textX, at.textY, at.width, at.barY), 50) << "the legend's text";
    EXPECT_GT(inkIn(at.barX + at.barWidth, at.barY, at.width, at.barY + at.barHeight), 50)
        << "ticks and labels";
    EXPECT_EQ(inkIn(64, 0, at.barX, at.height), 0);
  }
}

// Walls of B 1 and 1000 span three decades: the automatic scale is log, the dimmest wall at the
// bottom of the map, the brightest at its top, one of 10 a third of the way up. Linear, 10 is
// near the bottom.
TEST(FalseColour, ScaleGoesLogOverTwoDecades) {
  const SharedTempDir dir("render_outputs_test");
  // Left on screen: the wall x = 1; right: x = 0; centre: the back wall z = 1.
  const Result box = makeGreyBox({1000, 1, 10, 10, 10, 10});
  Options options = smallImage();
  options.smooth = false;
  options.falseColour = FalseColour::kRadiosity;
  const fs::path path = dir.path() / "walls.png";
  auto colourOf = [](double position) {
    const Colour c = colourAt(position);
    return std::array<int, 3>{c[0], c[1], c[2]};
  };
  for (Scale scale : {Scale::kAuto, Scale::kLog}) {
    options.scale = scale;
    renderImage(MPI_COMM_WORLD, box, options, path.string());
    const Picture map = readPng(path);
    EXPECT_EQ(map.at(8, 32), colourOf(0));
    EXPECT_EQ(map.at(55, 32), colourOf(1));
    EXPECT_EQ(map.at(32, 32), colourOf(1.0 / 3));
    EXPECT_EQ(map.at(0, 0), (std::array<int, 3>{0, 0, 0}));  // no surface: background
  }
  options.scale = Scale::kLinear;
  renderImage(MPI_COMM_WORLD, box, options, path.string());
  EXPECT_EQ(readPng(path).at(32, 32), colourOf(10.0 / 1000));
}

TEST(ColourScale, RangeAndTicks) {
  ColourScale linear = chooseScale(1, 50, Scale::kAuto);
  EXPECT_FALSE(linear.log);
  EXPECT_EQ(linear.low, 0);
  EXPECT_EQ(linear.high, 50);
  EXPECT_EQ(linear.ticks, (std::vector<double>{0, 10, 20, 30, 40, 50}));
  EXPECT_EQ(linear.position(25), 0.5);
  EXPECT_EQ(chooseScale(0, kPi, Scale::kAuto).high, 4);  // a round top

  ColourScale log = chooseScale(1, 1000, Scale::kAuto);
  EXPECT_TRUE(log.log);
  EXPECT_EQ(log.low, 1);
  EXPECT_EQ(log.high, 1000);
  EXPECT_EQ(log.ticks, (std::vector<double>{1, 10, 100, 1000}));
  EXPECT_NEAR(log.position(10), 1.0 / 3, 1e-15);
  EXPECT_EQ(log.position(0), 0);
  EXPECT_EQ(log.position(-1), 0);
  EXPECT_EQ(log.position(1e9), 1);
  EXPECT_FALSE(chooseScale(1, 99, Scale::kAuto).log);  // under two decades

  // At most six decades below the top; one at least, with ticks at 2 and 5 too.
  EXPECT_DOUBLE_EQ(chooseScale(1e-12, 1, Scale::kLog).low, 1e-6);
  ColourScale narrow = chooseScale(5, 5, Scale::kLog);
  EXPECT_EQ(narrow.low, 1);
  EXPECT_EQ(narrow.high, 10);
  EXPECT_EQ(narrow.ticks, (std::vector<double>{1, 2, 5, 10}));
  // Nothing lit: a unit scale.
  EXPECT_EQ(chooseScale(0, 0, Scale::kAuto).high, 1);
  EXPECT_EQ(chooseScale(0, 0, Scale::kLog).high, 1);
  // The map is viridis: matplotlib's colours at its ends and middle.
  EXPECT_EQ(colourAt(0), (Colour{68, 1, 84}));
  EXPECT_EQ(colourAt(0.5), (Colour{33, 145, 140}));
  EXPECT_EQ(colourAt(1), (Colour{253, 231, 37}));
  EXPECT_EQ(colourAt(-1), colourAt(0));
  EXPECT_EQ(colourAt(2), colourAt(1));
  EXPECT_EQ(tickLabel(0.30000000000000004), "0.3");
  EXPECT_EQ(tickLabel(1e-5), "1e-05");
  EXPECT_EQ(tickLabel(250000), "2.5e+05");
}

// A thermal map's scale spans its values' range, negative ones too (a net flux), from round
// ticks at or beyond its ends.
TEST(ColourScale, RangeScaleSpansTheValuesSignedOrNot) {
  const ColourScale temperature = rangeScale(300, 1000);
  EXPECT_FALSE(temperature.log);
  EXPECT_EQ(temperature.ticks, (std::vector<double>{200, 400, 600, 800, 1000}));
  EXPECT_EQ(temperature.position(1000), 1);
  const ColourScale flux = rangeScale(-3200, 18000);
  EXPECT_LE(flux.low, -3200);
  EXPECT_GE(flux.high, 18000);
  EXPECT_LT(flux.low, 0);
  EXPECT_EQ(flux.position(flux.low), 0);
  EXPECT_GE(flux.ticks.size(), 3u);
  EXPECT_LE(flux.ticks.size(), 7u);
  EXPECT_LT(rangeScale(5, 5).low, rangeScale(5, 5).high);  // one value: a scale still
}

// The labels' characters are all in the font: none drawn as the box that stands for a missing one.
TEST(BitmapFont, HasEveryCharacterOfTheLegend) {
  auto drawn = [](const std::string& text) {
    Canvas canvas(textWidth(text, 1), kCellHeight, {0, 0, 0});
    drawText(canvas, 0, 0, text, 1, {255, 255, 255});
    return std::string(canvas.rgb.begin(), canvas.rgb.end());
  };
  const std::string missing = drawn("\x01");
  const std::string legend = "0123456789.e+-radiosity B irradiance H unit of E W/m^2 log linear";
  std::set<char> characters;
  std::set<std::string> glyphs;
  for (char c : legend) {
    if (c == ' ') continue;
    EXPECT_NE(drawn(std::string(1, c)), missing) << c;
    characters.insert(c);
    glyphs.insert(drawn(std::string(1, c)));
  }
  EXPECT_EQ(glyphs.size(), characters.size()) << "two characters look alike";
  EXPECT_EQ(textWidth("1e+05", 2), (5 * kCellWidth - 1) * 2);
}

}  // namespace
}  // namespace radiosity::render
