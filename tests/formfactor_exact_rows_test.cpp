// Exact rows (Options::exactRows): Lambert's point-to-polygon formula against the closed form for
// a point and a rectangle, whole rows against the closed forms for rectangles (parallel plates,
// the faces of a cube), the choice of scenes that qualify, and rows that do not depend on how
// they are split across calls, threads and extensions; on floats, every row's sum kept
// (formfactor_exact_units_test.cpp: the rounding itself).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "analytic_view_factors.h"
#include "formfactor/formfactor.h"
#include "formfactor/polygon_factors.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::formfactor {
namespace {

// From a point on the normal through a corner of an a × b rectangle at distance c (Howell, B-3).
double pointToCornerOfRectangle(double a, double b, double c) {
  const double x = a / c, y = b / c, p = std::sqrt(1 + x * x), q = std::sqrt(1 + y * y);
  return (x / p * std::atan(y / p) + y / q * std::atan(x / q)) / (2 * std::numbers::pi);
}

TEST(PolygonFactors, PointToTriangleMatchesThePointToRectangleClosedForm) {
  for (const auto& [a, b, c] : {std::array<double, 3>{1, 1, 1}, {2, 0.5, 0.3}, {0.1, 3, 5}}) {
    // The rectangle [0, a] × [0, b] at height c, both triangles, seen from the origin facing up.
    const Triangle t1{Vec3{0, 0, c}, Vec3{a, 0, c}, Vec3{a, b, c}};
    const Triangle t2{Vec3{0, 0, c}, Vec3{a, b, c}, Vec3{0, b, c}};
    const Vec3 x{0, 0, 0}, up{0, 0, 1};
    EXPECT_NEAR(pointToTriangleFactor(x, up, t1) + pointToTriangleFactor(x, up, t2),
                pointToCornerOfRectangle(a, b, c), 1e-12);
  }
}

// The vectorised pass over a row's triangles gives what the single-point formula gives at the
// rule's points, to the bit (the same arithmetic), for every triangle, near, far or behind.
TEST(PolygonFactors, TheVectorisedThreePointPassIsThePointFormula) {
  const Mesh mesh = partition::refine(loadScene("builtin:cornell"), 2000);
  TriangleTable table;
  std::vector<Triangle> triangles;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    triangles.push_back({mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)});
    table.add(triangles.back());
  }
  const size_t n = triangles.size();
  ASSERT_GT(n, 100u);
  std::vector<double> a(n), b(n), c(n);
  for (int64_t i : {int64_t{0}, mesh.triangleCount() / 2, mesh.triangleCount() - 1}) {
    const PatchShape from(triangles[i], mesh.normal(i));
    threePointFactors(from, table, a.data(), b.data(), c.data());
    const Triangle& t = from.corners;
    const double near = 2.0 / 3, far = 1.0 / 6;
    const Vec3 points[3] = {near * t[0] + far * t[1] + far * t[2],
                            far * t[0] + near * t[1] + far * t[2],
                            far * t[0] + far * t[1] + near * t[2]};
    for (size_t j = 0; j < n; ++j) {
      EXPECT_EQ(a[j], pointToTriangleFactor(points[0], from.normal, triangles[j])) << i << " " << j;
      EXPECT_EQ(b[j], pointToTriangleFactor(points[1], from.normal, triangles[j])) << i << " " << j;
      EXPECT_EQ(c[j], pointToTriangleFactor(points[2], from.normal, triangles[j])) << i << " " << j;
    }
  }
}

// Rows [0, N) in one call.
SampleTally exactRows(const Mesh& mesh, int64_t samples = 16, int threads = 1,
                      bool onFloats = false) {
  SceneTracer tracer(mesh);
  Options options;
  options.raysPerPatch = samples;
  options.exactRows = true;
  options.threads = threads;
  options.singlePrecision = onFloats;
  Statistics statistics;
  SampleTally tally = sampleRows(tracer, mesh, 0, mesh.triangleCount(), options, statistics);
  EXPECT_EQ(statistics.raysCast, 0);
  EXPECT_GT(statistics.pairFactors, 0);
  return tally;
}

// F from the patches of source face `from` to those of `to`, area-weighted: the factor between
// the two faces.
double faceFactor(const Mesh& mesh, const SparseRows& rows, int64_t from, int64_t to) {
  double flux = 0, area = 0;
  for (int64_t i = 0; i < mesh.triangleCount(); ++i) {
    if (mesh.sourceFace[i] != from) continue;
    area += mesh.area(i);
    for (int64_t k = rows.rowStart[i]; k < rows.rowStart[i + 1]; ++k) {
      if (mesh.sourceFace[rows.column[k]] == to) flux += mesh.area(i) * rows.value[k];
    }
  }
  return flux / area;
}

TEST(ExactRows, ParallelAndPerpendicularPlatesMatchClosedForms) {
  struct Case {
    Mesh mesh;
    double exact;
  };
  std::vector<Case> cases;
  cases.push_back({testing::parallelPlates(1, 1, 1), testing::parallelRectangles(1, 1, 1)});
  cases.push_back({testing::parallelPlates(2, 1, 0.5), testing::parallelRectangles(2, 1, 0.5)});
  cases.push_back({testing::parallelPlates(1, 3, 0.05), testing::parallelRectangles(1, 3, 0.05)});
  cases.push_back(
      {loadScene("builtin:plates?angle=90"), testing::perpendicularRectangles(1, 1, 1)});
  for (Case& c : cases) {
    // Two triangles a plate, and hundreds; pair factors to 1e-5 (the refinement's tolerance is
    // 1e-4 of a pair where i and j are within i's size of each other).
    for (double maxArea : {1e9, 0.01}) {
      const Mesh mesh = partition::refine(c.mesh, maxArea);
      ASSERT_TRUE(everyPairUnoccluded(mesh));
      const SparseRows rows = toFormFactors(exactRows(mesh));
      EXPECT_NEAR(faceFactor(mesh, rows, 0, 1), c.exact, 1e-5 * c.exact)
          << mesh.triangleCount() << " patches";
    }
  }
}

TEST(ExactRows, TheCubesFaceFactorsMatchClosedFormsAndItsRowsSumToOne) {
  const Mesh cube = partition::refine(testing::closedBox(0.5, 0), 1.0 / 32);
  ASSERT_TRUE(everyPairUnoccluded(cube));
  const SparseRows rows = toFormFactors(exactRows(cube));
  // closedBox's faces: 0 and 1 opposite (z = 0, 1), 2 (y = 0) adjacent to both.
  EXPECT_NEAR(faceFactor(cube, rows, 0, 1), testing::parallelRectangles(1, 1, 1), 1e-6);
  EXPECT_NEAR(faceFactor(cube, rows, 0, 2), testing::perpendicularRectangles(1, 1, 1), 1e-6);
  EXPECT_NEAR(faceFactor(cube, rows, 2, 0), testing::perpendicularRectangles(1, 1, 1), 1e-6);
  EXPECT_EQ(faceFactor(cube, rows, 0, 0), 0.0);  // coplanar
  // Closed: the hemisphere of every point is covered, and the rows say so to round-off, as
  // sampled rows of a closed scene do (every ray hits).
  for (double sum : rowSums(rows)) EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST(ExactRows, OnlyScenesWhosePatchesHideNothingQualify) {
  EXPECT_TRUE(everyPairUnoccluded(testing::closedBox(0.5, 1)));
  EXPECT_TRUE(everyPairUnoccluded(testing::parallelPlates(1, 1, 1)));
  EXPECT_TRUE(everyPairUnoccluded(loadScene("builtin:box")));
  // A blocker between the plates, facing either way or both.
  EXPECT_FALSE(everyPairUnoccluded(testing::platesWithBlocker(true, false)));
  EXPECT_FALSE(everyPairUnoccluded(testing::platesWithBlocker(false, true)));
  EXPECT_FALSE(everyPairUnoccluded(testing::platesWithBlocker(true, true)));
  EXPECT_FALSE(everyPairUnoccluded(loadScene("builtin:cornell")));
  EXPECT_FALSE(everyPairUnoccluded(loadScene("builtin:city")));
  // A closed box with its normals out is no enclosure.
  Mesh inside_out = testing::closedBox(0.5, 1);
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_FALSE(everyPairUnoccluded(inside_out));

  const Mesh box = partition::refine(testing::closedBox(0.5, 1), 1.0 / 32);  // 192 patches
  EXPECT_TRUE(chooseRows(box, 24).exact);
  // Past kExactRowsMaxPatches, sampled however many rays: N² entries would not fit.
  const Mesh large = partition::refine(testing::closedBox(0.5, 1), 6.0 / 24000);
  ASSERT_GT(large.triangleCount(), kExactRowsMaxPatches);
  const RowsChoice tooMany = chooseRows(large, int64_t{1} << 20);
  EXPECT_FALSE(tooMany.exact);
  EXPECT_NE(tooMany.reason.find("exact rows are made for"), std::string::npos) << tooMany.reason;
  const RowsChoice few = chooseRows(box, 23);  // 192 > 8 × 23
  EXPECT_FALSE(few.exact);
  EXPECT_NE(few.reason.find("patches are more than"), std::string::npos) << few.reason;
  EXPECT_NE(few.reason.find("--rays 24 "), std::string::npos) << few.reason;  // what would do
  const RowsChoice blocked = chooseRows(testing::platesWithBlocker(true, true), 1024);
  EXPECT_FALSE(blocked.exact);
  EXPECT_NE(blocked.reason.find("hide"), std::string::npos) << blocked.reason;
}

bool same(const SampleTally& a, const SampleTally& b) {
  return a.firstRow == b.firstRow && a.samples == b.samples && a.rowStart == b.rowStart &&
         a.column == b.column && a.sum == b.sum;
}

TEST(ExactRows, TheSameOnAnySplitOnThreadsAndExtendedByMoreSamples) {
  const Mesh mesh = partition::refine(testing::closedBox(0.5, 1), 1.0 / 32);
  const int64_t n = mesh.triangleCount();
  const SampleTally whole = exactRows(mesh, 24);
  EXPECT_TRUE(same(exactRows(mesh, 24, 2), whole));
  SceneTracer tracer(mesh);
  Options options;
  options.exactRows = true;
  Statistics statistics;
  RowSampling sampling(tracer, mesh, options);
  SampleTally pieces;
  sampling.sampleInto(pieces, 0, n / 3, 0, 24, statistics);
  sampling.sampleInto(pieces, n / 3, n, 0, 24, statistics);
  EXPECT_TRUE(same(pieces, whole));
  const SampleTally first = sampling.sample(0, n, 0, 10, statistics);
  const SampleTally more = sampling.sample(0, n, 10, 14, statistics);
  EXPECT_TRUE(same(mergeSamples(first, more), whole));
}

// Whether a float holds units · 2^-32 exactly.
bool floatHolds(int64_t units) {
  const double value = std::ldexp(static_cast<double>(units), -32);
  return static_cast<double>(static_cast<float>(value)) == value;
}

// Exact rows for a store of floats: every value one a float holds, every closed row summing to
// 1 as on doubles (to the unit), each entry within a float's rounding (or two units) of the
// double row's; appended to a store of floats they give the same tally back.
TEST(ExactRows, OnFloatsEveryValueIsAFloatAndEveryRowKeepsItsSum) {
  // (1,536 patches: as in the scenes stored so, most entries below 2^-8; with a few hundred,
  // the small entries left take up to ten units each)
  const Mesh cube = partition::refine(testing::closedBox(0.5, 1), 1.0 / 256);
  const int64_t samples = 24;
  const SampleTally onDoubles = exactRows(cube, samples);
  const SampleTally onFloats = exactRows(cube, samples, 1, true);
  ASSERT_EQ(onFloats.rowCount(), cube.triangleCount());
  for (int64_t r = 0; r < onFloats.rowCount(); ++r) {
    int64_t sumFloats = 0, sumDoubles = 0;
    for (int64_t k = onDoubles.rowStart[r]; k < onDoubles.rowStart[r + 1]; ++k)
      sumDoubles += onDoubles.sum[k];
    std::vector<int64_t> doubleSum(static_cast<size_t>(cube.triangleCount()), 0);
    for (int64_t k = onDoubles.rowStart[r]; k < onDoubles.rowStart[r + 1]; ++k)
      doubleSum[onDoubles.column[k]] = onDoubles.sum[k];
    for (int64_t k = onFloats.rowStart[r]; k < onFloats.rowStart[r + 1]; ++k) {
      sumFloats += onFloats.sum[k];
      ASSERT_EQ(onFloats.sum[k] % samples, 0);
      const int64_t units = onFloats.sum[k] / samples,
                    before = doubleSum[onFloats.column[k]] / samples;
      EXPECT_TRUE(floatHolds(units)) << r << " " << onFloats.column[k];
      EXPECT_LE(std::abs(units - before),
                std::max<double>(2, std::ldexp(static_cast<double>(before), -23)))
          << r << " " << onFloats.column[k];
    }
    EXPECT_EQ(sumFloats, sumDoubles) << "row " << r;
    EXPECT_EQ(sumFloats, samples << 32) << "row " << r;  // closed
  }
  SplitRows store;
  store.singlePrecision = true;
  appendRows(store, onFloats);
  EXPECT_TRUE(same(store.tally(0, store.rowCount()), onFloats));
}

}  // namespace
}  // namespace radiosity::formfactor
