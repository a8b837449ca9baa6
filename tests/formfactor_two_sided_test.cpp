// Thin two-sided surfaces: two coincident faces back to back, each triangulated its own way.
// Each face gets its full view factor from its own side, whichever of the two Embree returns;
// a face with no front coincident with it still absorbs at its back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "analytic_view_factors.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "sampled_form_factors.h"
#include "test_scenes.h"

namespace radiosity::formfactor {
namespace {

using testing::kBlockerDown, testing::kBlockerUp, testing::kBottomPlate, testing::kTopPlate;

// F(plate → the blocker's face towards it), either plate: the unit square to the square
// [0.25, 0.75]² half a unit away.
double blockerFactor() {
  return testing::parallelRectangles({0, 1, 0, 1}, {0.25, 0.75, 0.25, 0.75}, 0.5);
}

TEST(AnalyticViewFactors, ParallelRectanglesAnywhereMeetTheOpposedFormAndReciprocity) {
  EXPECT_NEAR(testing::parallelRectangles({0, 1, 0, 1}, {0, 1, 0, 1}, 1),
              testing::parallelRectangles(1, 1, 1), 1e-12);
  EXPECT_NEAR(testing::parallelRectangles({0, 2, 0, 0.5}, {0, 2, 0, 0.5}, 0.7),
              testing::parallelRectangles(2, 0.5, 0.7), 1e-12);
  // A_1 F_12 = A_2 F_21 for rectangles apart in their planes.
  const testing::Rectangle r{0, 1, 0, 2}, s{0.5, 3, 1, 1.5};
  EXPECT_NEAR(2 * testing::parallelRectangles(r, s, 0.8),
              1.25 * testing::parallelRectangles(s, r, 0.8), 1e-12);
  // The blocker's value, as integrated by the midpoint rule on 400 × 400 points.
  EXPECT_NEAR(blockerFactor(), 0.129413, 1e-6);
}

// How the blocker's two faces are written: each four corners a, b, c, d of the square, the up
// face counter-clockwise seen from above, the down face from below.
enum class Blocker {
  kTwins,           ///< the same two triangles each, turned over
  kOtherDiagonals,  ///< each face split along its own diagonal
  kSubdivided,      ///< the down face two triangles, the up face 3 × 3 quads
  kObjQuads,        ///< OBJ quads, the up face's corners in reverse order (as exporters write
                    ///< it): the reader's fan splits it along the other diagonal
};
constexpr Blocker kBlockers[] = {Blocker::kTwins, Blocker::kOtherDiagonals, Blocker::kSubdivided,
                                 Blocker::kObjQuads};
const char* name(Blocker b) {
  switch (b) {
    case Blocker::kTwins:
      return "twins";
    case Blocker::kOtherDiagonals:
      return "other diagonals";
    case Blocker::kSubdivided:
      return "subdivided";
    case Blocker::kObjQuads:
      return "OBJ quads";
  }
  return "?";
}

// An OBJ scene read by the loader (no materials: form factors do not need them).
Mesh loadObj(const std::string& text) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("two_sided_test_" + std::to_string(::getpid()) + ".obj");
  std::ofstream(path) << text;
  Mesh mesh = loadScene(path.string());
  std::filesystem::remove(path);
  return mesh;
}

// testing::platesWithBlocker(true, true) with the blocker written as `blocker`: source faces as in
// testing::BlockerFace.
Mesh platesWithThinBlocker(Blocker blocker) {
  if (blocker == Blocker::kObjQuads) {
    return loadObj(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "v 0.25 0.25 0.5\nv 0.75 0.25 0.5\nv 0.75 0.75 0.5\nv 0.25 0.75 0.5\n"
        "f 1 2 3 4\nf 5 8 7 6\nf 9 12 11 10\nf 10 11 12 9\n");
  }
  Mesh mesh = testing::parallelPlates(1, 1, 1);
  const Rgb rho{0.5, 0.5, 0.5}, none{0, 0, 0};
  const Vec3 a{0.25, 0.25, 0.5}, b{0.75, 0.25, 0.5}, c{0.75, 0.75, 0.5}, d{0.25, 0.75, 0.5};
  if (blocker == Blocker::kTwins) {
    testing::addTwoSidedQuad(mesh, a, d, c, b, rho, none, false);
  } else if (blocker == Blocker::kOtherDiagonals) {
    testing::addQuad(mesh, a, d, c, b, rho, none);  // diagonal a–c
    testing::addQuad(mesh, b, c, d, a, rho, none);  // diagonal b–d
  } else {
    testing::addQuad(mesh, a, d, c, b, rho, none);
    testing::addSubdividedQuad(mesh, a, b, d, 3, rho, none);
  }
  return mesh;
}

// Samples per plate: 2 rows of 16,384 samples, or 32 refined rows of 1,024.
constexpr int64_t kSamples = 32768;

// The rows of one plate of a blocker scene, as it is (2 triangles a face) or refined to 32
// patches a plate and put in curve order as `solve` does (coincident triangles then are not
// neighbours by id); which of two coincident triangles Embree returns depends on their order,
// so `reversed` turns the triangle order round. The area-weighted F(plate → source face f) for
// each f, and the plate's statistics.
struct PlateRows {
  Mesh patches;
  int64_t twinned = 0;  ///< triangles with a twin (SceneTracer::twinnedPatches)
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
    std::reverse(p.patches.label.begin(), p.patches.label.end());
  }
  SceneTracer tracer(p.patches);
  p.twinned = tracer.twinnedPatches();
  p.toFace.assign(*std::max_element(p.patches.sourceFace.begin(), p.patches.sourceFace.end()) + 1,
                  0.0);
  const int64_t rays = kSamples / (refined ? 32 : 2);
  double area = 0;
  for (int64_t i = 0; i < p.patches.triangleCount(); ++i) {
    if (p.patches.sourceFace[i] != plate) continue;
    const SparseRows row =
        testing::sampledFormFactors(tracer, p.patches, i, i + 1, {rays, 11}, p.statistics);
    for (int64_t k = 0; k < row.nonzeros(); ++k) {
      p.toFace[p.patches.sourceFace[row.column[k]]] += p.patches.area(i) * row.value[k];
    }
    area += p.patches.area(i);
    ++p.rows;
  }
  for (double& f : p.toFace) f /= area;
  return p;
}

// Binomial bound on the standard deviation of a plate's area-weighted F (equal patches,
// kSamples samples in all; Sobol' samples do better): 3 of it is a two-sided false-failure rate
// below 0.3 % per check.
double sigma(double f) { return std::sqrt(f * (1 - f) / double(kSamples)); }

// From `plate`, the blocker's face towards it gets F = blockerFactor(), the face turned away
// gets nothing, and no ray is absorbed by a back face, for every way of writing the blocker.
void expectFullViewFactorFrom(int64_t plate, int64_t towards, int64_t away) {
  const double exact = blockerFactor();
  for (Blocker b : kBlockers) {
    for (int variant = 0; variant < 4; ++variant) {
      const bool refined = variant & 1, reversed = variant & 2;
      const PlateRows p = plateRows(platesWithThinBlocker(b), plate, refined, reversed);
      ASSERT_EQ(p.rows, refined ? 32 : 2);
      // As written, only twins are twins: the others take the second trace.
      if (!refined) {
        EXPECT_EQ(p.twinned > 0, b == Blocker::kTwins) << name(b);
      }
      const std::string what =
          std::string(name(b)) + (refined ? ", refined" : "") + (reversed ? ", reversed" : "");
      std::printf("thin blocker (%s): F(plate %lld -> blocker) = %.5f, exact %.5f\n", what.c_str(),
                  static_cast<long long>(plate), p.toFace[towards], exact);
      EXPECT_NEAR(p.toFace[towards], exact, 3 * sigma(exact)) << what;
      EXPECT_EQ(p.toFace[away], 0.0) << what;
      EXPECT_EQ(p.statistics.backFaceHits, 0) << what;
    }
  }
}

TEST(ThinSurfaces, ATwoSidedBlockerGetsItsFullViewFactorFromBelowHoweverTriangulated) {
  expectFullViewFactorFrom(kBottomPlate, kBlockerDown, kBlockerUp);
}

TEST(ThinSurfaces, ATwoSidedBlockerGetsItsFullViewFactorFromAboveHoweverTriangulated) {
  expectFullViewFactorFrom(kTopPlate, kBlockerUp, kBlockerDown);
}

TEST(ThinSurfaces, AOneSidedBlockerSeenFromBehindStillAbsorbs) {
  const double exact = blockerFactor();
  // Only the up-facing face: the bottom plate sees its back, with no front near it.
  const PlateRows p = plateRows(testing::platesWithBlocker(false, true), kBottomPlate, false);
  const int64_t blocker = 2;  // its source face
  EXPECT_EQ(p.toFace[blocker], 0.0);
  // The rays that met it are counted as back-face hits: about the view factor's share (the
  // plate's patches have equal areas) ...
  const double share = double(p.statistics.backFaceHits) / double(p.statistics.raysCast);
  std::printf("one-sided blocker seen from behind: back-face hits / rays = %.5f\n", share);
  EXPECT_NEAR(share, exact, 3 * sigma(exact));
  // ... and the top plate behind it gets nothing through it: what it gets past a two-sided
  // blocker (the same rays; a ray or two may split differently on the blocker's diagonal).
  const PlateRows twoSided = plateRows(platesWithThinBlocker(Blocker::kTwins), kBottomPlate, false);
  EXPECT_NEAR(p.toFace[kTopPlate], twoSided.toFace[kTopPlate], 2.0 / (kSamples / 2));

  // Facing the plate, the one-sided blocker gets what the two-sided one gets.
  const PlateRows facing = plateRows(testing::platesWithBlocker(true, false), kBottomPlate, true);
  EXPECT_EQ(facing.statistics.backFaceHits, 0);
  EXPECT_NEAR(facing.toFace[kBlockerDown], exact, 3 * sigma(exact));
}

TEST(ThinSurfaces, TwinsAreFoundByPositionWithAnyCornerOrderAndOnlyWithOppositeOrientation) {
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

// Two unit squares at z = 0 and z = gap, a ray straight up through both: the lower one turned
// away from the ray (its back towards it), the upper one facing it. Both queries' hits.
struct StackedHits {
  std::optional<SceneTracer::Hit> single;
  int64_t batchPatch;
  bool batchFront;
};
StackedHits stackedHits(double gap) {
  Mesh mesh;
  const Rgb rho{0.5, 0.5, 0.5}, none{0, 0, 0};
  testing::addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, rho, none);  // faces up
  testing::addQuad(mesh, {0, 0, gap}, {0, 1, gap}, {1, 1, gap}, {1, 0, gap}, rho, none);
  SceneTracer tracer(mesh);
  const Vec3 origin{0.3, 0.6, -1}, direction{0, 0, 1};
  SceneTracer::RayBatch rays;
  rays.resize(1);
  rays.set(0, origin, direction, std::numeric_limits<double>::infinity());
  SceneTracer::HitBatch hits;
  tracer.intersect(rays, hits);
  return {tracer.intersect(origin, direction, 0.0), hits.patch[0], hits.front[0] == 1};
}

TEST(ThinSurfaces, ABackFaceIsReportedUnlessAFrontLiesWithinTheCoincidenceWindow) {
  // The scene's size is √2 (the gap aside): the window is 1.4e-5.
  const double window = SceneTracer::kCoincidentFaces * std::sqrt(2.0);
  for (double gap : {0.0, 0.3 * window, 3 * window, 0.01}) {
    const StackedHits h = stackedHits(gap);
    const bool coincident = gap < window;
    ASSERT_TRUE(h.single.has_value());
    // Patches 0, 1: the lower square (its back); 2, 3: the upper one (its front).
    EXPECT_EQ(h.single->patch >= 2, coincident) << "gap " << gap;
    EXPECT_EQ(h.single->geometricNormal.z < 0, coincident) << "gap " << gap;
    EXPECT_NEAR(h.single->distance, coincident ? 1 + gap : 1, 1e-6) << "gap " << gap;
    EXPECT_EQ(h.batchPatch, h.single->patch) << "gap " << gap;
    EXPECT_EQ(h.batchFront, coincident) << "gap " << gap;
  }
}

TEST(ThinSurfaces, InsideOutWallsAbsorbEveryRayThatReachesThem) {
  // A lamp cube wound right (normals out) in a room wound inside out (normals out): every ray
  // the lamp casts meets the back of a wall with no front near it.
  Mesh scene = testing::closedBox(0.5, 0.0, 1.0);
  for (Triangle& t : scene.triangles) std::swap(t[1], t[2]);
  Mesh lamp = testing::closedBox(0.5, 1.0, 0.5);
  for (Triangle& t : lamp.triangles) std::swap(t[1], t[2]);
  const auto base = static_cast<int64_t>(scene.vertices.size());
  for (Vec3 v : lamp.vertices) scene.vertices.push_back(v + Vec3{0.25, 0.25, 0.25});
  for (size_t t = 0; t < lamp.triangles.size(); ++t) {
    const Triangle& c = lamp.triangles[t];
    scene.triangles.push_back({c[0] + base, c[1] + base, c[2] + base});
    scene.sourceFace.push_back(6 + lamp.sourceFace[t]);
    scene.reflectance.push_back(lamp.reflectance[t]);
    scene.emission.push_back(lamp.emission[t]);
  }
  const Mesh patches = partition::refine(scene, 0.05);
  SceneTracer tracer(patches);
  Statistics statistics;
  int64_t lampRays = 0;
  for (int64_t i = 0; i < patches.triangleCount(); ++i) {
    if (patches.sourceFace[i] < 6) continue;
    testing::sampledFormFactors(tracer, patches, i, i + 1, {256, 3}, statistics);
    lampRays += 256;
  }
  EXPECT_EQ(statistics.raysCast, lampRays);
  EXPECT_EQ(statistics.backFaceHits, lampRays);
}

// Both queries, on rays that cross the blocker from either side: the hit is always the face
// towards the ray, with its normal, and u, v locate the hit point on that patch's corners.
TEST(ThinSurfaces, BothQueriesReportTheFaceTowardsTheRay) {
  for (int variant = 0; variant < 8; ++variant) {
    const Blocker b = kBlockers[variant / 2];
    const bool refined = variant & 1;
    const Mesh mesh =
        refined ? partition::refine(platesWithThinBlocker(b), 1.0 / 32) : platesWithThinBlocker(b);
    SceneTracer tracer(mesh);
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
    SceneTracer::RayBatch rays;
    rays.resize(origins.size());
    for (size_t k = 0; k < origins.size(); ++k) {
      rays.set(k, origins[k], directions[k], std::numeric_limits<double>::infinity());
    }
    SceneTracer::HitBatch hits;
    tracer.intersect(rays, hits);
    for (size_t k = 0; k < origins.size(); ++k) {
      const auto hit = tracer.intersect(origins[k], directions[k], 0.0);
      ASSERT_TRUE(hit.has_value());
      const int64_t expected = directions[k].z > 0 ? kBlockerDown : kBlockerUp;
      EXPECT_EQ(mesh.sourceFace[hit->patch], expected)
          << "ray " << k << ", " << name(b) << (refined ? ", refined" : "");
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
