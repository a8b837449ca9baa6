// Sampled form factors: rows of F against closed forms and closed enclosures, the same rows on
// any split across ranks, threads and pieces, and the error of each estimator as rays grow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "analytic_view_factors.h"
#include "core/error.h"
#include "cornell_floor_light.h"
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

TEST(HemisphereSampling, OneBuildingCityEscapesToTheSky) {
  // builtin:city with one building: the roof sees only sky, the walls only ground (less than
  // the half an infinite ground would give, more than the ground straight in front), the
  // ground only walls.
  const Mesh city = loadScene("builtin:city?buildings=1&element=2&seed=5");
  Statistics statistics;
  const SparseRows rows = allRows(city, 256, 13, statistics);
  EXPECT_GT(statistics.escapedRays, 0);
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (int64_t t = 0; t < city.triangleCount(); ++t) {
    if (city.label[t] != 1) continue;
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], city.corner(t, k)[a]),
        hi[a] = std::max(hi[a], city.corner(t, k)[a]);
      }
    }
  }
  double wallSum = 0, wallArea = 0, lowXWall = 0, lowXArea = 0;
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    const double sum = rowSum(rows, r);
    const bool roof = city.sourceFace[r] == 1, ground = city.label[r] == 0;
    if (roof) {
      EXPECT_EQ(sum, 0) << "roof patch " << r;
    }
    if (ground) {
      EXPECT_LT(sum, 0.5);
    } else if (!roof) {
      wallSum += city.area(r) * sum, wallArea += city.area(r);
      if (city.sourceFace[r] == 2) lowXWall += city.area(r) * sum, lowXArea += city.area(r);
    }
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      const int64_t c = rows.column[k];
      EXPECT_NE(city.label[c] == 0, ground) << "row " << r << " sees " << c;
      EXPECT_NE(city.sourceFace[c], 1) << "row " << r << " sees the roof";
    }
  }
  EXPECT_LT(wallSum / wallArea, 0.5);
  // The wall at low x (source face 2): the ground strip in front of it, as wide as the wall
  // (l = depth in z), from its foot to the ground's edge at x = 0.
  const double front = testing::perpendicularRectangles(hi.z - lo.z, hi.y, lo.x);
  EXPECT_GT(lowXWall / lowXArea, front);
  EXPECT_LT(lowXWall / lowXArea, 0.5);
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

// In a large scene (2^17 patches or more) rows of few samples are summed from their sorted hits,
// rows of many in the dense accumulator: the two ways agree bit for bit (few, then many more,
// merged = many at once), on one thread and on two.
TEST(ExtensibleSampling, FewSampleRowsOfALargeSceneEqualTheDenseSums) {
  Mesh rooms = partition::orderAlongCurve(
      partition::refineToCount(loadScene("builtin:rooms?patches=140000"), 140000));
  ASSERT_GE(rooms.triangleCount(), int64_t{1} << 17);
  SceneTracer tracer(rooms);
  // A few rows are enough (the sums, not the scene, are under test), yet enough rays that a
  // call of 16 rays a row runs on two threads (RowSampling gives a thread 2^14 rays at least).
  const int64_t rows = 2100;
  for (int threads : {1, 2}) {
    Statistics s;
    SampleTally few =
        sampleRows(tracer, rooms, 0, rows, {16, 4, Estimator::kHemisphere, 0, threads}, s);
    SampleTally more =
        sampleRows(tracer, rooms, 0, rows, {300, 4, Estimator::kHemisphere, 16, threads}, s);
    SampleTally all =
        sampleRows(tracer, rooms, 0, rows, {316, 4, Estimator::kHemisphere, 0, threads}, s);
    EXPECT_TRUE(sameTally(mergeSamples(few, more), all)) << threads << " threads";
    EXPECT_GT(few.column.size(), static_cast<size_t>(rows));
  }
}

// What the form-factor stage does: rows in pieces written into one tally as they are sampled,
// on one thread and on two, give the tally of one call bit for bit; a piece that does not follow
// on from the tally's rows is refused.
TEST(ExtensibleSampling, RowsSampledIntoOneTallyEqualOneCall) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 8000);
  SceneTracer tracer(cornell);
  const int64_t n = cornell.triangleCount();
  for (int threads : {1, 2}) {
    const Options options{64, 7, Estimator::kEmitterMis, 0, threads};
    Statistics whole, pieces;
    SampleTally all = sampleRows(tracer, cornell, 0, n, options, whole);
    RowSampling sampling(tracer, cornell, options);
    SampleTally joined;
    for (int64_t p = 0; p < 7; ++p) {
      sampling.sampleInto(joined, n * p / 7, n * (p + 1) / 7, 0, 64, pieces);
      reserveRows(joined, n);
    }
    EXPECT_TRUE(sameTally(joined, all)) << threads << " threads";
    EXPECT_EQ(pieces.raysCast, whole.raysCast);
    EXPECT_THROW(sampling.sampleInto(joined, 0, 1, 0, 64, pieces), Error);
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

TEST(EmitterMis, ReducesTheErrorOfDirectLightOnTheCornellFloorAtEqualRays) {
  Mesh cornell = partition::refine(loadScene("builtin:cornell"), 12000);
  SceneTracer tracer(cornell);
  const std::vector<int64_t> floor = testing::cornellFloor(cornell, 40);
  ASSERT_GE(floor.size(), 20u);
  const auto reference =
      testing::floorDirectIrradiance(cornell, tracer, floor, 8192, Estimator::kEmitterMis, 99);
  // Equal rays: MIS casts two per sample.
  const auto hemisphere =
      testing::floorDirectIrradiance(cornell, tracer, floor, 256, Estimator::kHemisphere, 1);
  const auto mis =
      testing::floorDirectIrradiance(cornell, tracer, floor, 128, Estimator::kEmitterMis, 1);
  const double hemisphereError = testing::rmsErrorOverMean(hemisphere, reference),
               misError = testing::rmsErrorOverMean(mis, reference);
  ASSERT_TRUE(std::isfinite(hemisphereError) && std::isfinite(misError)) << "no light on the floor";
  std::printf(
      "direct light on the Cornell floor, RMS error / mean at 256 rays: hemisphere "
      "%.4f, MIS %.4f (%.1fx smaller)\n",
      hemisphereError, misError, hemisphereError / misError);
  EXPECT_LT(misError, hemisphereError / 5);
}

}  // namespace
}  // namespace radiosity::formfactor
