// Pair factors of triangles near each other (formfactor/contour_factors.h): nearly touching
// parallel squares and their pieces against the closed forms for parallel rectangles, from a
// tenth of their size down to a hundred-thousandth, and the error each quotes covering the error
// it makes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "analytic_view_factors.h"
#include "formfactor/contour_factors.h"
#include "formfactor/polygon_factors.h"

namespace radiosity::formfactor {
namespace {

// The rectangle [x0, x1] × [y0, y1] at height z as two triangles facing `up` (or down).
std::vector<PatchShape> rectangle(testing::Rectangle r, double z, bool up) {
  const Vec3 a{r.x0, r.y0, z}, b{r.x1, r.y0, z}, c{r.x1, r.y1, z}, d{r.x0, r.y1, z};
  const Vec3 normal{0, 0, up ? 1.0 : -1.0};
  return {PatchShape(Triangle{a, b, c}, normal), PatchShape(Triangle{a, c, d}, normal)};
}

// F from r (z = 0, facing up) to s (z = c, facing down) summed over their triangles, by
// triangleToTriangleFactor as exact rows compute it, and the errors the near pairs quote.
struct Summed {
  double factor = 0, quoted = 0;
};
Summed rectangleFactor(testing::Rectangle r, testing::Rectangle s, double c) {
  const std::vector<PatchShape> from = rectangle(r, 0, true), to = rectangle(s, c, false);
  TriangleTable table;
  for (const PatchShape& t : to) table.add(t.corners);
  Summed sum;
  double area = 0;
  for (const PatchShape& i : from) {
    std::array<std::vector<double>, 3> at;
    for (auto& a : at) a.resize(to.size());
    threePointFactors(i, table, at[0].data(), at[1].data(), at[2].data());
    const double a = 0.5 * length(cross(i.corners[1] - i.corners[0], i.corners[2] - i.corners[0]));
    area += a;
    for (size_t j = 0; j < to.size(); ++j) {
      double quoted = 0;
      sum.factor += a * triangleToTriangleFactor(i, to[j], {at[0][j], at[1][j], at[2][j]}, &quoted);
      sum.quoted += a * quoted;
    }
  }
  sum.factor /= area;
  sum.quoted /= area;
  return sum;
}

TEST(NearFactors, NearlyTouchingSquaresMatchTheParallelRectanglesClosedForm) {
  const testing::Rectangle unit{0, 1, 0, 1};
  for (double c : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5}) {
    const Summed f = rectangleFactor(unit, unit, c);
    const double exact = testing::parallelRectangles(unit, unit, c);
    EXPECT_NEAR(f.factor, exact, 1e-10) << "distance " << c;
    EXPECT_LE(f.factor, 1.0) << "distance " << c;
    EXPECT_LE(f.quoted, 1e-10) << "distance " << c;
  }
}

// Pieces of the plates, as a refined mesh has them: offset, overlapping in part, or one of them
// far smaller than the other.
TEST(NearFactors, PiecesOfNearlyTouchingPlatesMatchTheirClosedForms) {
  const std::vector<std::array<testing::Rectangle, 2>> pairs = {
      {{{0, 0.5, 0, 0.5}, {0.5, 1, 0, 0.5}}},          // side by side, sharing an edge's projection
      {{{0, 0.5, 0, 0.5}, {0.25, 0.75, 0.25, 0.75}}},  // a quarter overlapping
      {{{0, 1, 0, 1}, {0.4, 0.45, 0.4, 0.45}}},        // a small one under a large one
      {{{0.4, 0.45, 0.4, 0.45}, {0, 1, 0, 1}}},
      {{{0, 0.5, 0, 0.5}, {0.6, 1, 0, 0.5}}},  // apart by more than their distance
  };
  for (const auto& [r, s] : pairs) {
    for (double c : {1e-2, 1e-4, 1e-5}) {
      const Summed f = rectangleFactor(r, s, c);
      const double exact = testing::parallelRectangles(r, s, c);
      EXPECT_NEAR(f.factor, exact, 1e-10) << r.x0 << " " << s.x0 << " distance " << c;
      EXPECT_LE(std::abs(f.factor - exact), f.quoted) << r.x0 << " distance " << c;
    }
  }
}

// A_i F_ij = A_j F_ji for each near pair: the contour integral is symmetric in i and j.
TEST(NearFactors, NearPairsAreReciprocal) {
  const std::vector<PatchShape> from = rectangle({0, 1, 0, 1}, 0, true),
                                to = rectangle({0.3, 0.7, 0.1, 0.9}, 1e-4, false);
  for (const PatchShape& i : from) {
    for (const PatchShape& j : to) {
      const double ai =
          0.5 * length(cross(i.corners[1] - i.corners[0], i.corners[2] - i.corners[0]));
      const double aj =
          0.5 * length(cross(j.corners[1] - j.corners[0], j.corners[2] - j.corners[0]));
      const double ij = contourFactor(i, j).value, ji = contourFactor(j, i).value;
      EXPECT_NEAR(ai * ij, aj * ji, 1e-10 * ai);
    }
  }
}

// Triangles sharing an edge at right angles (a cube's corner): the logarithm is singular on the
// edge, integrably; the pair's factor matches the closed form for perpendicular rectangles.
TEST(NearFactors, PerpendicularSquaresSharingAnEdgeMatchTheirClosedForm) {
  const Vec3 o{0, 0, 0}, x{1, 0, 0}, xy{1, 1, 0}, y{0, 1, 0}, xz{1, 0, 1}, z{0, 0, 1};
  const std::vector<PatchShape> floor = {PatchShape(Triangle{o, x, xy}, Vec3{0, 0, 1}),
                                         PatchShape(Triangle{o, xy, y}, Vec3{0, 0, 1})};
  const std::vector<PatchShape> wall = {PatchShape(Triangle{o, xz, x}, Vec3{0, 1, 0}),
                                        PatchShape(Triangle{o, z, xz}, Vec3{0, 1, 0})};
  double sum = 0;
  for (const PatchShape& i : floor)
    for (const PatchShape& j : wall) sum += 0.5 * contourFactor(i, j).value;
  EXPECT_NEAR(sum, testing::perpendicularRectangles(1, 1, 1), 1e-10);
}

}  // namespace
}  // namespace radiosity::formfactor
