// Twins: thin two-sided surfaces written as coincident faces back to back. Each face gets its
// full view factor from its own side, whichever of the two Embree returns, on any refinement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "analytic_view_factors.h"
#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "sampled_form_factors.h"
#include "test_scenes.h"

namespace radiosity::formfactor {
namespace {

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
