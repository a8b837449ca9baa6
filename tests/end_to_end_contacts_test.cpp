// Contacts cut into the mesh, end to end: the published Cornell box, its floor one quad running
// under the blocks, against builtin:cornell's floor cut by hand around them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "end_to_end_fixture.h"

namespace radiosity::testing {
namespace {

using Footprint = std::vector<std::array<double, 2>>;  // (x, z), counter-clockwise

// The blocks' footprints on the Cornell floor (mm), as published.
const std::vector<Footprint> kFootprints = {{{130, 65}, {290, 114}, {240, 272}, {82, 225}},
                                            {{423, 247}, {472, 406}, {314, 456}, {265, 296}}};

double footprintArea(const Footprint& f) {
  double twice = 0;
  for (size_t k = 0; k < f.size(); ++k) {
    const auto& a = f[k];
    const auto& b = f[(k + 1) % f.size()];
    twice += a[0] * b[1] - b[0] * a[1];
  }
  return twice / 2;
}

// Distance from (x, z) to the footprint: 0 inside.
double distanceTo(const Footprint& f, double x, double z) {
  bool inside = true;
  double nearest = 1e300;
  for (size_t k = 0; k < f.size(); ++k) {
    const auto& a = f[k];
    const auto& b = f[(k + 1) % f.size()];
    const double ex = b[0] - a[0], ez = b[1] - a[1];
    inside = inside && ex * (z - a[1]) - ez * (x - a[0]) > 0;
    const double t =
        std::clamp(((x - a[0]) * ex + (z - a[1]) * ez) / (ex * ex + ez * ez), 0.0, 1.0);
    nearest = std::min(nearest, std::hypot(x - a[0] - t * ex, z - a[1] - t * ez));
  }
  return inside ? 0 : nearest;
}

bool isFloor(const Result& r, int64_t t) {
  return r.normal[t].y > 0.99 && r.mesh.corner(t, 0).y == 0 && r.mesh.corner(t, 1).y == 0;
}

// Area-weighted mean B of the visible floor within `band` mm of a block (outside it), per channel.
Rgb floorBesideTheBlocks(const Result& r, double band) {
  Rgb sum{0, 0, 0};
  double area = 0;
  for (int64_t t = 0; t < r.mesh.triangleCount(); ++t) {
    if (!isFloor(r, t) || (!r.hidden.empty() && r.hidden[t])) continue;
    const Vec3 c = r.mesh.centroid(t);
    double d = 1e300;
    for (const Footprint& f : kFootprints) d = std::min(d, distanceTo(f, c.x, c.z));
    if (d <= 0 || d > band) continue;
    for (int k = 0; k < 3; ++k) sum[k] += r.area[t] * r.radiosity[t][k];
    area += r.area[t];
  }
  for (double& s : sum) s /= area;
  return sum;
}

TEST_F(EndToEnd, ThePublishedCornellFloorIsCutTheSameOnOneTwoAndThreeRanks) {
  std::vector<Result> results;
  ASSERT_NO_FATAL_FAILURE(
      solveOnEach({{1, 1}, {2, 1}, {3, 1}},
                  " 'builtin:cornell?cut_floor=0' --max-area 2000 --rays 16 -q -o ", results));
  for (const Result& r : results) {
    EXPECT_EQ(r.mesh.triangles, results[0].mesh.triangles);
    EXPECT_EQ(r.mesh.vertices, results[0].mesh.vertices);
    EXPECT_EQ(r.hidden, results[0].hidden);
  }
  // The floor under the blocks is patches of its own, hidden: exactly the footprints' area.
  const Result& r = results[1];
  ASSERT_EQ(r.hidden.size(), static_cast<size_t>(r.mesh.triangleCount()));
  double hidden = 0;
  for (int64_t t = 0; t < r.mesh.triangleCount(); ++t) {
    if (!r.hidden[t]) continue;
    EXPECT_TRUE(isFloor(r, t)) << "patch " << t;
    EXPECT_EQ(r.radiosity[t], r.mesh.emission[t]) << "a hidden patch is left out: B = E";
    hidden += r.area[t];
  }
  const double footprints = footprintArea(kFootprints[0]) + footprintArea(kFootprints[1]);
  EXPECT_NEAR(hidden, footprints, 1e-9 * footprints);
}

TEST_F(EndToEnd, ThePublishedCornellFloorGivesTheHandCutFloorsAnswer) {
  const std::string options = " --rays 256 -q -o ";
  ProgramRun cut = radiosity(2, "solve builtin:cornell" + options + path("cut.h5"));
  ASSERT_EQ(cut.exitCode, 0) << cut.output;
  ProgramRun published =
      radiosity(2, "solve 'builtin:cornell?cut_floor=0'" + options + path("published.h5"));
  ASSERT_EQ(published.exitCode, 0) << published.output;
  // The hidden floor's rows see only the blocks' insides: not a winding to warn about.
  EXPECT_EQ(published.output.find("hit the back of a face"), std::string::npos) << published.output;
  ProgramRun asGiven = radiosity(
      2, "solve 'builtin:cornell?cut_floor=0' --contacts off" + options + path("as_given.h5"));
  ASSERT_EQ(asGiven.exitCode, 0) << asGiven.output;
  const Result a = readResult(path("cut.h5")), b = readResult(path("published.h5")),
               c = readResult(path("as_given.h5"));
  // The floor within 20 mm of the blocks' feet, where patches reaching under a block darkened
  // the light (9 % low here, 7 % measured by `verify` at the default settings), and the whole
  // visible floor. Meshes differ (cut by hand, cut here, refined to their own shapes), so the
  // averages agree to the discretisation and sampling error at 256 rays (measured: 0.3 % and
  // 1.2 % beside the blocks, 0.03 % over the floor), not to round-off.
  const Rgb handCut = floorBesideTheBlocks(a, 20), cutHere = floorBesideTheBlocks(b, 20),
            uncut = floorBesideTheBlocks(c, 20);
  const Rgb handCutFloor = floorBesideTheBlocks(a, 1e9),
            cutHereFloor = floorBesideTheBlocks(b, 1e9);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(cutHere[k], handCut[k], 0.025 * handCut[k]) << "channel " << k;
    EXPECT_NEAR(cutHereFloor[k], handCutFloor[k], 0.005 * handCutFloor[k]) << "channel " << k;
    EXPECT_LT(uncut[k], 0.95 * handCut[k]) << "channel " << k << ": uncut, not darkened?";
  }
}

}  // namespace
}  // namespace radiosity::testing
