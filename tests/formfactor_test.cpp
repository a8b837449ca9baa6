#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "analytic_view_factors.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "sampled_form_factors.h"
#include "test_scenes.h"

namespace radiosity::formfactor {
namespace {

SparseRows allRows(const Mesh& mesh, int64_t rays, uint64_t seed, Statistics& statistics,
                   Estimator estimator = Estimator::kHemisphere) {
  SceneTracer tracer(mesh);
  return testing::sampledFormFactors(tracer, mesh, 0, mesh.triangleCount(), {rays, seed, estimator},
                                     statistics);
}

double rowSum(const SparseRows& rows, int64_t r) {
  double sum = 0;
  for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) sum += rows.value[k];
  return sum;
}

TEST(AnalyticViewFactors, MatchPublishedValues) {
  EXPECT_NEAR(testing::parallelRectangles(1, 1, 1), 0.19982, 5e-6);
  EXPECT_NEAR(testing::perpendicularRectangles(1, 1, 1), 0.20004, 5e-6);
}

TEST(SceneTracer, HitNormalPointsToTheLitSideAsMeshNormal) {
  Mesh box = partition::refine(testing::closedBox(0.5, 1.0), 0.1);
  SceneTracer tracer(box);
  for (int64_t t = 0; t < box.triangleCount(); ++t) {
    // Aim from the box centre at the triangle's centroid.
    Vec3 centre{0.5, 0.5, 0.5}, direction = normalize(box.centroid(t) - centre);
    auto hit = tracer.intersect(centre, direction, 0.0);
    ASSERT_TRUE(hit.has_value());
    EXPECT_GT(dot(normalize(hit->geometricNormal), box.normal(hit->patch)), 0.999);
  }
}

TEST(HemisphereSampling, RowsOfAClosedBoxSumToOne) {
  Mesh box = partition::refine(testing::closedBox(0.5, 1.0), 0.02);
  Statistics statistics;
  SparseRows rows = allRows(box, 64, 7, statistics);
  EXPECT_EQ(statistics.escapedRays, 0);
  EXPECT_EQ(statistics.backFaceHits, 0);
  for (int64_t r = 0; r < rows.rowCount(); ++r) EXPECT_NEAR(rowSum(rows, r), 1.0, 1e-12);
}

TEST(HemisphereSampling, NoSelfHitsAndSortedColumns) {
  Mesh box = partition::refine(testing::closedBox(0.5, 1.0), 0.05);
  Statistics statistics;
  SparseRows rows = allRows(box, 32, 3, statistics);
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      EXPECT_NE(rows.column[k], r);
      if (k > rows.rowStart[r]) {
        EXPECT_LT(rows.column[k - 1], rows.column[k]);
      }
    }
  }
}

// The receiver's area-weighted row sum towards the emitter estimates F(receiver → emitter).
void expectViewFactor(const Mesh& scene, double exact, int64_t rays,
                      Estimator estimator = Estimator::kHemisphere) {
  Mesh patches = partition::refine(scene, scene.totalArea() / 400);
  Statistics statistics;
  SparseRows rows = allRows(patches, rays, 11, statistics, estimator);
  double weighted = 0, receiverArea = 0;
  int64_t receivers = 0;
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    if (patches.emission[r][0] > 0) continue;
    double toEmitter = 0;
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      if (patches.emission[rows.column[k]][0] > 0) toEmitter += rows.value[k];
    }
    weighted += patches.area(r) * toEmitter;
    receiverArea += patches.area(r);
    ++receivers;
  }
  double estimate = weighted / receiverArea;
  // Binomial variance per row, patches of about equal area: σ² ≈ F(1 − F) / (N · patches)
  // (an upper bound for MIS, whose variance is lower).
  double sigma = std::sqrt(exact * (1 - exact) / (double(rays) * receivers));
  EXPECT_NEAR(estimate, exact, 3 * sigma) << "rays " << rays << ", σ " << sigma;
}

TEST(HemisphereSampling, MatchesParallelRectangles) {
  expectViewFactor(testing::parallelPlates(1, 1, 1), testing::parallelRectangles(1, 1, 1), 256);
  expectViewFactor(testing::parallelPlates(2, 1, 0.5), testing::parallelRectangles(2, 1, 0.5), 256);
  expectViewFactor(testing::parallelPlates(1, 3, 2), testing::parallelRectangles(1, 3, 2), 256);
}

TEST(EmitterMis, MatchesParallelAndPerpendicularRectangles) {
  for (Estimator e : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    expectViewFactor(testing::parallelPlates(1, 1, 1), testing::parallelRectangles(1, 1, 1), 256,
                     e);
    expectViewFactor(testing::parallelPlates(1, 3, 0.2), testing::parallelRectangles(1, 3, 0.2),
                     256, e);
    expectViewFactor(loadScene("builtin:plates?angle=90"),
                     testing::perpendicularRectangles(1, 1, 1), 256, e);
  }
}

TEST(HemisphereSampling, MatchesPerpendicularRectanglesWithACommonEdge) {
  // Emitter 1 (along x) × 2 (along z) on the floor y = 0 facing +y; receiver 1 × 0.5 on the
  // wall z = 0 facing +z. From the receiver (height h = 0.5) to the floor (w2 = 2), l = 1.
  Mesh scene;
  testing::addQuad(scene, {0, 0, 0}, {0, 0, 2}, {1, 0, 2}, {1, 0, 0}, {0, 0, 0}, {1, 1, 1});
  testing::addQuad(scene, {0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0}, {0, 0, 0});
  expectViewFactor(scene, testing::perpendicularRectangles(1, 0.5, 2), 256);
}

TEST(HemisphereSampling, MatchesThePerpendicularBuiltinPlates) {
  // builtin:plates?angle=90: emitter w × h on the floor, receiver w × h standing on the common
  // edge (length w): F(receiver → emitter) with H = h / w, W = h / w.
  expectViewFactor(loadScene("builtin:plates?angle=90"), testing::perpendicularRectangles(1, 1, 1),
                   256);
  expectViewFactor(loadScene("builtin:plates?angle=90&width=2&height=0.7"),
                   testing::perpendicularRectangles(2, 0.7, 0.7), 256);
}

TEST(HemisphereSampling, RowsDoNotDependOnHowPatchesAreSplitAcrossRanks) {
  Mesh patches = partition::refine(testing::closedBox(0.5, 1.0), 0.02);
  SceneTracer tracer(patches);
  Statistics s1, s2, s3;
  const int64_t n = patches.triangleCount(), cut = n / 3;
  SparseRows whole = testing::sampledFormFactors(tracer, patches, 0, n, {100, 5}, s1);
  SparseRows head = testing::sampledFormFactors(tracer, patches, 0, cut, {100, 5}, s2);
  SparseRows tail = testing::sampledFormFactors(tracer, patches, cut, n, {100, 5}, s3);
  for (int64_t r = 0; r < n; ++r) {
    const SparseRows& part = r < cut ? head : tail;
    int64_t local = r - part.firstRow;
    ASSERT_EQ(whole.rowStart[r + 1] - whole.rowStart[r],
              part.rowStart[local + 1] - part.rowStart[local]);
    for (int64_t k = 0; k < whole.rowStart[r + 1] - whole.rowStart[r]; ++k) {
      EXPECT_EQ(whole.column[whole.rowStart[r] + k], part.column[part.rowStart[local] + k]);
      EXPECT_EQ(whole.value[whole.rowStart[r] + k], part.value[part.rowStart[local] + k]);
    }
  }
}

TEST(HemisphereSampling, OtherSeedGivesOtherRows) {
  Mesh patches = partition::refine(testing::closedBox(0.5, 1.0), 0.05);
  Statistics s;
  EXPECT_NE(allRows(patches, 64, 1, s).value, allRows(patches, 64, 2, s).value);
}

TEST(HemisphereSampling, OpenScenesCountEscapesAndBackFaces) {
  Mesh plates = testing::parallelPlates(1, 1, 1);
  Statistics statistics;
  allRows(plates, 64, 1, statistics);
  EXPECT_EQ(statistics.raysCast, 4 * 64);
  EXPECT_GT(statistics.escapedRays, 0);
  // Flip the receiver: the emitter's rays now hit its back and are absorbed.
  for (int64_t t = 2; t < 4; ++t) std::swap(plates.triangles[t][1], plates.triangles[t][2]);
  Statistics flipped;
  allRows(plates, 64, 1, flipped);
  EXPECT_GT(flipped.backFaceHits, 0);
}

TEST(HemisphereSampling, BackFaceHitsAreCountedPerLabel) {
  // A closed box labelled per face (source face f → label f), with face 1 turned inside out:
  // every back-face hit is on face 1, and nothing hits the back of a correctly wound face.
  Mesh box = testing::closedBox(0.5, 1.0);
  for (int f = 0; f < 6; ++f) box.labelNames.push_back("face " + std::to_string(f));
  for (int64_t f : box.sourceFace) box.label.push_back(static_cast<int32_t>(f));
  for (int64_t t = 0; t < box.triangleCount(); ++t) {
    if (box.sourceFace[t] == 1) std::swap(box.triangles[t][1], box.triangles[t][2]);
  }
  Mesh patches = partition::orderAlongCurve(partition::refine(box, 0.05));
  ASSERT_TRUE(patches.hasLabels());
  Statistics statistics;
  allRows(patches, 64, 3, statistics);
  ASSERT_EQ(statistics.backFaceHitsByLabel.size(), 6u);
  EXPECT_GT(statistics.backFaceHits, 0);
  EXPECT_EQ(statistics.backFaceHitsByLabel[1], statistics.backFaceHits);

  // Without labels the split stays empty.
  box.label.clear();
  box.labelNames.clear();
  Statistics unlabelled;
  allRows(box, 16, 3, unlabelled);
  EXPECT_TRUE(unlabelled.backFaceHitsByLabel.empty());
  EXPECT_GT(unlabelled.backFaceHits, 0);
}

bool sameTally(const SampleTally& a, const SampleTally& b) {
  return a.firstRow == b.firstRow && a.samples == b.samples && a.rowStart == b.rowStart &&
         a.column == b.column && a.sum == b.sum;
}

TEST(ExtensibleSampling, NThenMMoreEqualsNPlusMBitForBit) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 8000);
  SceneTracer tracer(cornell);
  for (Estimator e : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    Statistics s;
    const int64_t n = cornell.triangleCount();
    SampleTally all = sampleRows(tracer, cornell, 0, n, {96, 3, e}, s);
    SampleTally first = sampleRows(tracer, cornell, 0, n, {64, 3, e}, s);
    SampleTally more = sampleRows(tracer, cornell, 0, n, {32, 3, e, 64}, s);
    EXPECT_TRUE(sameTally(mergeSamples(first, more), all));
    SparseRows a = toFormFactors(all), b = toFormFactors(mergeSamples(first, more));
    EXPECT_EQ(a.value, b.value);
  }
}

TEST(ExtensibleSampling, ThreadsGiveTheSameRows) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 8000);
  SceneTracer tracer(cornell);
  for (Estimator e : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    Statistics one, three;
    const int64_t n = cornell.triangleCount();
    SampleTally serial = sampleRows(tracer, cornell, 0, n, {64, 9, e, 0, 1}, one);
    SampleTally threaded = sampleRows(tracer, cornell, 0, n, {64, 9, e, 0, 3}, three);
    EXPECT_TRUE(sameTally(serial, threaded));
    EXPECT_EQ(one.raysCast, three.raysCast);
    EXPECT_EQ(one.backFaceHits, three.backFaceHits);
  }
}

// What a checkpointed run does: rows in pieces and samples in pieces, from one RowSampling,
// give the tally of one call bit for bit, and the statistics count each ray once.
TEST(ExtensibleSampling, PiecesOfRowsAndOfSamplesEqualOneCall) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 8000);
  SceneTracer tracer(cornell);
  for (Estimator e : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    const int64_t n = cornell.triangleCount();
    Statistics whole, pieces;
    SampleTally all = sampleRows(tracer, cornell, 0, n, {96, 5, e, 0, 2}, whole);
    RowSampling sampling(tracer, cornell, {96, 5, e, 0, 2});
    SampleTally joined;
    const int64_t cut = n / 3;
    for (auto [first, end] : {std::pair<int64_t, int64_t>{0, cut}, {cut, n}}) {
      SampleTally part = mergeSamples(sampling.sample(first, end, 0, 40, pieces),
                                      sampling.sample(first, end, 40, 56, pieces));
      for (int64_t r = 1; r <= part.rowCount(); ++r)
        joined.rowStart.push_back(static_cast<int64_t>(joined.column.size()) + part.rowStart[r]);
      joined.column.insert(joined.column.end(), part.column.begin(), part.column.end());
      joined.sum.insert(joined.sum.end(), part.sum.begin(), part.sum.end());
      joined.samples = part.samples;
    }
    EXPECT_TRUE(sameTally(joined, all));
    EXPECT_EQ(pieces.raysCast, whole.raysCast);
  }
}

// MIS is unbiased: in a closed sphere its rows sum to 1 on average. (Shadow rays that had to
// hit the sampled patch itself lost grazing samples to neighbouring facets: 0.9994 here.)
TEST(EmitterMis, RowsOfAClosedSphereSumToOneOnAverage) {
  const Mesh sphere = loadScene("builtin:sphere?rho=0.7&level=3");
  SceneTracer tracer(sphere);
  Statistics s;
  const SparseRows rows = testing::sampledFormFactors(tracer, sphere, 0, sphere.triangleCount(),
                                                      {2048, 1, Estimator::kEmitterMis}, s);
  EXPECT_NEAR(s.sumRowSums / static_cast<double>(rows.rowCount()), 1.0, 1e-4);
}

TEST(HemisphereSampling, RowsOfAClosedSphereSumToOne) {
  Mesh sphere = loadScene("builtin:sphere?level=2");
  Statistics statistics;
  SparseRows rows = allRows(sphere, 64, 1, statistics);
  EXPECT_EQ(statistics.escapedRays, 0);
  for (int64_t r = 0; r < rows.rowCount(); ++r) EXPECT_NEAR(rowSum(rows, r), 1.0, 1e-12);
  std::vector<int64_t> histogram = rowSumHistogram(rows);
  EXPECT_EQ(histogram[rowSumBinEdges().size() - 2], rows.rowCount());  // all in [1 ± 1e-9]
}

// RMS error over seeds of F(receiver → emitter) for one 1×1 receiver patch pair at distance 1.
double platesRmsError(int64_t rays, Estimator estimator) {
  Mesh plates = testing::parallelPlates(1, 1, 1);
  SceneTracer tracer(plates);
  const double exact = testing::parallelRectangles(1, 1, 1);
  double squares = 0;
  const int seeds = 64;
  for (int seed = 1; seed <= seeds; ++seed) {
    Statistics s;
    SparseRows rows =
        testing::sampledFormFactors(tracer, plates, 2, 4, {rays, uint64_t(seed), estimator}, s);
    double estimate = 0;  // both receiver triangles have the same area
    for (int64_t r = 0; r < 2; ++r) estimate += 0.5 * rowSum(rows, r);
    squares += (estimate - exact) * (estimate - exact);
  }
  return std::sqrt(squares / seeds);
}

TEST(HemisphereSampling, ErrorShrinksAtLeastLikeOneOverSqrtRays) {
  // Stratified (Sobol') samples converge at least as fast as independent ones: over a 64×
  // sweep the error must fall by at least 8× (1/√64), with 25 % slack for the seed sample.
  for (Estimator e : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    const double coarse = platesRmsError(16, e), fine = platesRmsError(1024, e);
    EXPECT_LT(fine, 1.25 * coarse / 8) << "coarse " << coarse << " fine " << fine;
    EXPECT_GT(coarse, 0);
  }
}

// Direct irradiance of the Cornell floor's patches: H_i = Σ_{j emitting} F_ij E_j (red).
std::vector<double> floorDirectIrradiance(const Mesh& cornell, const SceneTracer& tracer,
                                          int64_t rays, Estimator estimator, uint64_t seed,
                                          const std::vector<int64_t>& floor) {
  std::vector<double> irradiance;
  for (int64_t i : floor) {
    Statistics s;
    SparseRows row =
        testing::sampledFormFactors(tracer, cornell, i, i + 1, {rays, seed, estimator}, s);
    double h = 0;
    for (int64_t k = 0; k < row.nonzeros(); ++k)
      h += row.value[k] * cornell.emission[row.column[k]][0];
    irradiance.push_back(h);
  }
  return irradiance;
}

TEST(EmitterMis, ReducesTheErrorOfDirectLightOnTheCornellFloorAtEqualRays) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 12000);
  SceneTracer tracer(cornell);
  std::vector<int64_t> floor;
  for (int64_t t = 0; t < cornell.triangleCount(); ++t) {
    if (cornell.normal(t).y > 0.99 && cornell.centroid(t).y < 1 && floor.size() < 40)
      floor.push_back(t);
  }
  ASSERT_GE(floor.size(), 20u);
  const auto reference =
      floorDirectIrradiance(cornell, tracer, 8192, Estimator::kEmitterMis, 99, floor);
  // Equal rays: MIS casts two per sample.
  const auto hemisphere =
      floorDirectIrradiance(cornell, tracer, 256, Estimator::kHemisphere, 1, floor);
  const auto mis = floorDirectIrradiance(cornell, tracer, 128, Estimator::kEmitterMis, 1, floor);
  // RMS error relative to the mean irradiance (per-patch relative errors would be ruled by the
  // patches in half shadow).
  double hemisphereError = 0, misError = 0, mean = 0;
  for (size_t p = 0; p < floor.size(); ++p) {
    hemisphereError += std::pow(hemisphere[p] - reference[p], 2);
    misError += std::pow(mis[p] - reference[p], 2);
    mean += reference[p];
  }
  mean /= floor.size();
  ASSERT_GT(mean, 0);
  hemisphereError = std::sqrt(hemisphereError / floor.size()) / mean;
  misError = std::sqrt(misError / floor.size()) / mean;
  std::printf(
      "direct light on the Cornell floor, RMS error / mean at 256 rays: hemisphere "
      "%.4f, MIS %.4f (%.1fx smaller)\n",
      hemisphereError, misError, hemisphereError / misError);
  EXPECT_LT(misError, hemisphereError / 5);
}

// ---- Twins: thin two-sided surfaces written as coincident faces back to back ----

// From a point to a parallel rectangle at distance c (a differential element to a parallel
// rectangle with one corner straight above it, in Howell's catalog): the |dx| × |dy| rectangle,
// signed by quadrant so that four corner rectangles superpose to any rectangle.
double pointToCornerRectangle(double dx, double dy, double c) {
  const double X = std::abs(dx) / c, Y = std::abs(dy) / c;
  const double sx = std::sqrt(1 + X * X), sy = std::sqrt(1 + Y * Y);
  const double f =
      (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2 * std::numbers::pi);
  return (dx < 0) != (dy < 0) ? -f : f;
}

// From the unit square at z = 0 to the parallel square [lo, hi]² at height c: the point
// factor integrated by the midpoint rule on n × n points (smooth integrand: error O(n^-2),
// 1e-6 at n = 200 for the blocker).
double unitSquareToParallelSquare(double lo, double hi, double c, int n = 200) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      sum += pointToCornerRectangle(hi - x, hi - y, c) - pointToCornerRectangle(lo - x, hi - y, c) -
             pointToCornerRectangle(hi - x, lo - y, c) + pointToCornerRectangle(lo - x, lo - y, c);
    }
  }
  return sum / (double(n) * n);
}

TEST(AnalyticViewFactors, PointToRectangleIntegratesToTheClosedForms) {
  // The same integration reproduces the unit plates' published value ...
  EXPECT_NEAR(unitSquareToParallelSquare(0, 1, 1), testing::parallelRectangles(1, 1, 1), 1e-5);
  // ... and the blocker's value is converged.
  EXPECT_NEAR(unitSquareToParallelSquare(0.25, 0.75, 0.5),
              unitSquareToParallelSquare(0.25, 0.75, 0.5, 400), 2e-6);
  EXPECT_NEAR(unitSquareToParallelSquare(0.25, 0.75, 0.5), 0.129413, 2e-6);
}

int64_t countFace(const Mesh& patches, int64_t face) {
  return std::count(patches.sourceFace.begin(), patches.sourceFace.end(), face);
}

constexpr int64_t kTwinRays = 16384;

// The rows of one plate of a blocker scene, as it is (2 triangles a face) or refined to 32
// patches a plate (8 a blocker face, all of equal area) and put in curve order as `solve` does,
// so that twins are not neighbours by id (which of two coincident triangles Embree returns
// depends on their order, so `reversed` turns the triangle order round): the area-weighted
// F(plate → source face f) for each f, and the plate's statistics.
struct PlateRows {
  Mesh patches;
  int64_t twinned = 0;
  int64_t rows = 0;
  std::vector<double> toFace;
  Statistics statistics;
};
PlateRows plateRows(const Mesh& scene, int64_t plate, bool refined, bool reversed = false) {
  PlateRows p;
  p.patches = refined ? partition::orderAlongCurve(partition::refine(scene, 1.0 / 32)) : scene;
  if (reversed) {
    std::reverse(p.patches.triangles.begin(), p.patches.triangles.end());
    std::reverse(p.patches.sourceFace.begin(), p.patches.sourceFace.end());
    std::reverse(p.patches.reflectance.begin(), p.patches.reflectance.end());
    std::reverse(p.patches.emission.begin(), p.patches.emission.end());
  }
  SceneTracer tracer(p.patches);
  p.twinned = tracer.twinnedPatches();
  p.toFace.assign(*std::max_element(p.patches.sourceFace.begin(), p.patches.sourceFace.end()) + 1,
                  0.0);
  double area = 0;
  for (int64_t i = 0; i < p.patches.triangleCount(); ++i) {
    if (p.patches.sourceFace[i] != plate) continue;
    const SparseRows row =
        testing::sampledFormFactors(tracer, p.patches, i, i + 1, {kTwinRays, 11}, p.statistics);
    for (int64_t k = 0; k < row.nonzeros(); ++k) {
      p.toFace[p.patches.sourceFace[row.column[k]]] += p.patches.area(i) * row.value[k];
    }
    area += p.patches.area(i);
    ++p.rows;
  }
  for (double& f : p.toFace) f /= area;
  return p;
}

// Binomial bound on the standard deviation of an area-weighted F over `rows` equal patches of
// kTwinRays samples each (Sobol' samples do better).
double twinSigma(double f, int64_t rows) {
  return std::sqrt(f * (1 - f) / (double(kTwinRays) * rows));
}

TEST(Twins, AThinTwoSidedBlockerGetsItsFullViewFactorFromBelow) {
  using testing::kBlockerDown, testing::kBlockerUp, testing::kBottomPlate;
  const double exact = unitSquareToParallelSquare(0.25, 0.75, 0.5);
  for (int variant = 0; variant < 8; ++variant) {
    const bool refined = variant & 1, share = variant & 2, reversed = variant & 4;
    PlateRows p =
        plateRows(testing::platesWithBlocker(true, true, share), kBottomPlate, refined, reversed);
    // Both faces refined alike: every blocker patch has its twin.
    const int64_t blockerPatches = refined ? 8 : 2;
    ASSERT_EQ(countFace(p.patches, kBlockerDown), blockerPatches);
    EXPECT_EQ(p.twinned, 2 * blockerPatches) << "shared vertices " << share;
    ASSERT_EQ(p.rows, refined ? 32 : 2);
    std::printf(
        "thin blocker (refined %d, shared vertices %d, reversed %d): F(bottom -> "
        "blocker) = %.5f, exact %.5f\n",
        refined, share, reversed, p.toFace[kBlockerDown], exact);
    EXPECT_NEAR(p.toFace[kBlockerDown], exact, 3 * twinSigma(exact, p.rows))
        << "refined " << refined << ", shared vertices " << share << ", reversed " << reversed;
    // Nothing reaches the up-facing face from below, and no hit is absorbed by a back face.
    EXPECT_EQ(p.toFace[kBlockerUp], 0.0);
    EXPECT_EQ(p.statistics.backFaceHits, 0);
  }
}

TEST(Twins, AThinTwoSidedBlockerGetsItsFullViewFactorFromAbove) {
  using testing::kBlockerDown, testing::kBlockerUp, testing::kTopPlate;
  const double exact = unitSquareToParallelSquare(0.25, 0.75, 0.5);
  for (int variant = 0; variant < 4; ++variant) {
    const bool refined = variant & 1, reversed = variant & 2;
    PlateRows p = plateRows(testing::platesWithBlocker(true, true), kTopPlate, refined, reversed);
    std::printf("thin blocker (refined %d, reversed %d): F(top -> blocker) = %.5f, exact %.5f\n",
                refined, reversed, p.toFace[kBlockerUp], exact);
    EXPECT_NEAR(p.toFace[kBlockerUp], exact, 3 * twinSigma(exact, p.rows))
        << "refined " << refined << ", reversed " << reversed;
    EXPECT_EQ(p.toFace[kBlockerDown], 0.0);
    EXPECT_EQ(p.statistics.backFaceHits, 0);
  }
}

TEST(Twins, AOneSidedBlockerSeenFromBehindStillAbsorbs) {
  using testing::kBottomPlate;
  const double exact = unitSquareToParallelSquare(0.25, 0.75, 0.5);
  // Only the up-facing face: the bottom plate sees its back, which has no twin.
  PlateRows p = plateRows(testing::platesWithBlocker(false, true), kBottomPlate, true);
  const int64_t blocker = 2;  // its source face
  ASSERT_EQ(countFace(p.patches, blocker), 8);
  EXPECT_EQ(p.twinned, 0);
  EXPECT_EQ(p.toFace[blocker], 0.0);
  // The rays that met it are counted as back-face hits: about the view factor's share (the
  // plate's patches have equal areas).
  const double share = double(p.statistics.backFaceHits) / double(p.statistics.raysCast);
  std::printf("one-sided blocker seen from behind: back-face hits / rays = %.5f\n", share);
  EXPECT_NEAR(share, exact, 3 * twinSigma(exact, p.rows));

  // Facing the plate, the one-sided blocker gets what the two-sided one gets.
  PlateRows facing = plateRows(testing::platesWithBlocker(true, false), kBottomPlate, true);
  EXPECT_EQ(facing.statistics.backFaceHits, 0);
  EXPECT_NEAR(facing.toFace[testing::kBlockerDown], exact, 3 * twinSigma(exact, facing.rows));
}

TEST(Twins, FoundByPositionWithAnyCornerOrderAndOnlyWithOppositeOrientation) {
  Mesh mesh;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  for (Vec3 p : {a, b, c, b, c, a, c, b, a, a, b, c}) mesh.vertices.push_back(p);
  // 0: (a, b, c); 1: (b, c, a), the same orientation; 2: (c, b, a), turned over; 3: shares
  // vertex indices with 0, turned over: (a, c, b).
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {0, 2, 1}};
  // 4: a triangle elsewhere with no partner; 5: degenerate (two corners on one position).
  mesh.vertices.push_back({0, 0, 1});
  mesh.vertices.push_back({1, 0, 1});
  mesh.vertices.push_back({0, 1, 1});
  mesh.triangles.push_back({12, 13, 14});
  mesh.triangles.push_back({9, 10, 9});
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    mesh.sourceFace.push_back(static_cast<int64_t>(t));
    mesh.reflectance.push_back({0.5, 0.5, 0.5});
    mesh.emission.push_back({0, 0, 0});
  }
  SceneTracer tracer(mesh);
  EXPECT_EQ(tracer.twin(0), 2);  // of the two turned over, the smaller id
  EXPECT_EQ(tracer.twin(1), 2);
  EXPECT_EQ(tracer.twin(2), 0);
  EXPECT_EQ(tracer.twin(3), 0);
  EXPECT_EQ(tracer.twin(4), -1);
  EXPECT_EQ(tracer.twin(5), -1);
  EXPECT_EQ(tracer.twinnedPatches(), 4);

  // No coincident faces: no twins, nothing stored.
  SceneTracer box(testing::closedBox(0.5, 1.0));
  EXPECT_EQ(box.twinnedPatches(), 0);
  EXPECT_EQ(box.twin(0), -1);
}

// Both queries, on rays that cross the blocker from either side: the hit is always the face
// towards the ray, with its normal, and u, v locate the hit point on that patch's corners.
TEST(Twins, IntersectReportsTheFaceTowardsTheRay) {
  for (bool share : {false, true}) {
    const Mesh mesh = partition::refine(testing::platesWithBlocker(true, true, share), 1.0 / 32);
    SceneTracer tracer(mesh);
    ASSERT_GT(tracer.twinnedPatches(), 0);
    SceneTracer::RayBatch rays;
    std::vector<Vec3> origins, directions;
    for (int i = 0; i < 9; ++i) {
      for (int j = 0; j < 9; ++j) {
        const double x = 0.26 + 0.48 * i / 8, y = 0.26 + 0.48 * j / 8;
        for (double dz : {1.0, -1.0}) {
          // Up from z = 0.1 or down from z = 0.9, tilted a little.
          origins.push_back({x - 0.02, y + 0.005, dz > 0 ? 0.1 : 0.9});
          directions.push_back(normalize(Vec3{0.025, -0.0125, 0.4 * dz}));
        }
      }
    }
    rays.resize(origins.size());
    for (size_t k = 0; k < origins.size(); ++k) {
      rays.originX[k] = float(origins[k].x), rays.originY[k] = float(origins[k].y);
      rays.originZ[k] = float(origins[k].z);
      rays.directionX[k] = float(directions[k].x), rays.directionY[k] = float(directions[k].y);
      rays.directionZ[k] = float(directions[k].z);
      rays.tFar[k] = std::numeric_limits<float>::infinity();
    }
    SceneTracer::HitBatch hits;
    tracer.intersect(rays, hits);
    for (size_t k = 0; k < origins.size(); ++k) {
      const auto hit = tracer.intersect(origins[k], directions[k], 0.0);
      ASSERT_TRUE(hit.has_value());
      const int64_t expected = directions[k].z > 0 ? testing::kBlockerDown : testing::kBlockerUp;
      EXPECT_EQ(mesh.sourceFace[hit->patch], expected) << "ray " << k << " shared " << share;
      EXPECT_LT(dot(hit->geometricNormal, directions[k]), 0);
      EXPECT_GT(dot(normalize(hit->geometricNormal), mesh.normal(hit->patch)), 0.999);
      const Vec3 point = origins[k] + hit->distance * directions[k];
      const Vec3 fromUv = (1 - hit->u - hit->v) * mesh.corner(hit->patch, 0) +
                          hit->u * mesh.corner(hit->patch, 1) + hit->v * mesh.corner(hit->patch, 2);
      EXPECT_LT(length(point - fromUv), 1e-5);
      // The batch says the same.
      EXPECT_EQ(hits.patch[k], hit->patch);
      EXPECT_EQ(hits.front[k], 1);
      EXPECT_NEAR(hits.distance[k], hit->distance, 1e-6);
      EXPECT_NEAR(hits.u[k], hit->u, 1e-6);
      EXPECT_NEAR(hits.v[k], hit->v, 1e-6);
    }
  }
}

}  // namespace
}  // namespace radiosity::formfactor
