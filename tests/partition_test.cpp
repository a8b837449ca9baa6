#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "io/scene/scene.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::partition {
namespace {

// How many triangles use each undirected edge.
std::map<std::pair<int64_t, int64_t>, int> edgeUse(const Mesh& mesh) {
  std::map<std::pair<int64_t, int64_t>, int> use;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      int64_t a = t[k], b = t[(k + 1) % 3];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  }
  return use;
}

TEST(Refine, RespectsTheAreaBoundAndKeepsTheArea) {
  Mesh box = testing::closedBox(0.5, 1.0);
  MeshingReport report;
  Mesh patches = refine(box, 0.01, &report);
  EXPECT_GT(patches.triangleCount(), 6 * 50);
  for (int64_t t = 0; t < patches.triangleCount(); ++t) EXPECT_LE(patches.area(t), 0.01);
  EXPECT_NEAR(patches.totalArea(), 6.0, 1e-12);
  EXPECT_EQ(report.patches, patches.triangleCount());
  EXPECT_LE(report.maxPatchArea, 0.01);
  EXPECT_LT(report.worstAspectRatio, 4.0);  // longest-edge bisection keeps shapes
}

TEST(Refine, IsConforming) {
  // A closed box stays watertight only if no T-junction appears: every edge in two triangles.
  Mesh patches = refine(testing::closedBox(0.5, 1.0), 0.003);
  for (const auto& [edge, count] : edgeUse(patches)) {
    ASSERT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
  }
}

TEST(Refine, KeepsWindingSourceFaceAndMaterial) {
  Mesh box = testing::closedBox(0.5, 1.0);
  box.reflectance[3] = {0.1, 0.2, 0.3};
  Mesh patches = refine(box, 0.02);
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    int64_t face = patches.sourceFace[t];
    // Triangles 2f and 2f+1 of the box make face f; both have its normal.
    EXPECT_NEAR(dot(patches.normal(t), box.normal(2 * face)), 1.0, 1e-12);
  }
  // Input triangle 3 belongs to face 1; its children carry its material.
  int withMaterial = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    if (patches.reflectance[t] == Rgb{0.1, 0.2, 0.3}) {
      ++withMaterial;
      EXPECT_EQ(patches.sourceFace[t], 1);
    }
  }
  EXPECT_GT(withMaterial, 0);
}

TEST(Refine, NoBoundMeansNoChange) {
  Mesh box = testing::closedBox(0.5, 1.0);
  Mesh same = refine(box, 0.0);
  EXPECT_EQ(same.triangles, box.triangles);
}

TEST(Refine, IsDeterministic) {
  Mesh a = orderAlongCurve(refine(testing::closedBox(0.5, 1.0), 0.004));
  Mesh b = orderAlongCurve(refine(testing::closedBox(0.5, 1.0), 0.004));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
}

TEST(RefineToCount, LandsNearTheTargetWithinTheBound) {
  // Bisection alone moves the count in steps of up to ×2 on a uniform mesh such as the box;
  // the last round, largest first, lands on the target instead.
  for (const auto& [name, scene] : {std::pair{"box", testing::closedBox(0.5, 1.0)},
                                    std::pair{"cornell", loadScene("builtin:cornell")}}) {
    for (int64_t target : {100, 1000, 1500, 3000, 7000}) {
      SCOPED_TRACE(std::string(name) + " target " + std::to_string(target));
      MeshingReport report;
      Mesh patches = refineToCount(scene, target, &report);
      EXPECT_GE(patches.triangleCount(), target);
      EXPECT_LE(patches.triangleCount(), target + target / 4);
      EXPECT_NEAR(report.areaBound, scene.totalArea() / target, 1e-9 * scene.totalArea());
      EXPECT_NEAR(patches.totalArea(), scene.totalArea(), 1e-9 * scene.totalArea());
      // Only patches the last round left whole exceed the bound, and not by much here (the
      // Cornell floor's pieces around the blocks come in many sizes).
      double largest = 0;
      for (int64_t t = 0; t < patches.triangleCount(); ++t) {
        largest = std::max(largest, patches.area(t));
      }
      EXPECT_EQ(report.maxPatchArea, largest);
      EXPECT_LE(largest, 4.5 * report.areaBound);
      EXPECT_EQ(report.patches, patches.triangleCount());
      EXPECT_EQ(refineToCount(scene, target).triangles, patches.triangles);  // deterministic
    }
  }
}

TEST(RefineToCount, IsConformingOnAClosedBox) {
  for (const auto& [edge, count] : edgeUse(refineToCount(testing::closedBox(0.5, 1.0), 2500))) {
    ASSERT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
  }
}

TEST(RefineToCount, LeavesAFineEnoughSceneAlone) {
  Mesh box = testing::closedBox(0.5, 1.0);
  MeshingReport report;
  EXPECT_EQ(refineToCount(box, 12, &report).triangles, box.triangles);
  EXPECT_EQ(refineToCount(box, 5).triangles, box.triangles);
  EXPECT_EQ(report.areaBound, 0);
  EXPECT_EQ(report.refinementRounds, 0);
}

TEST(OrderAlongCurve, IsAPermutationOfTheTriangles) {
  Mesh patches = refine(testing::closedBox(0.5, 1.0), 0.01);
  Mesh sorted = orderAlongCurve(patches);
  auto a = patches.triangles, b = sorted.triangles;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_EQ(sorted.sourceFace.size(), patches.sourceFace.size());
}

TEST(RefineAndOrder, CarryTheLabels) {
  Mesh box = testing::closedBox(0.5, 1.0);
  box.labelNames = {"a", "b", "c", "d", "e", "f"};
  for (int64_t f : box.sourceFace) box.label.push_back(static_cast<int32_t>(f));
  const Mesh patches = orderAlongCurve(refine(box, 0.01));
  ASSERT_EQ(patches.label.size(), patches.triangles.size());
  EXPECT_EQ(patches.labelNames, box.labelNames);
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    EXPECT_EQ(patches.label[t], patches.sourceFace[t]);  // children keep the parent's label
  }
  // No labels in, none out.
  EXPECT_TRUE(orderAlongCurve(refine(testing::closedBox(0.5, 1.0), 0.01)).label.empty());
}

// `scaled` is `reference` with every coordinate times `scale`: the same patches in the same
// order, from the same source faces, with the same corners up to rounding.
void expectScaledCopy(const Mesh& reference, const Mesh& scaled, double scale) {
  ASSERT_EQ(scaled.triangleCount(), reference.triangleCount());
  Vec3 lo, hi;
  reference.boundingBox(lo, hi);
  const Vec3 diagonal = hi - lo;
  const double tolerance = 1e-9 * scale * std::sqrt(dot(diagonal, diagonal));
  int64_t otherFace = 0, moved = 0;
  for (int64_t t = 0; t < reference.triangleCount(); ++t) {
    if (scaled.sourceFace[t] != reference.sourceFace[t]) ++otherFace;
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = scaled.corner(t, k) - scale * reference.corner(t, k);
      if (std::sqrt(dot(d, d)) > tolerance) ++moved;
    }
  }
  EXPECT_EQ(otherFace, 0) << "patches from another source face";
  EXPECT_EQ(moved, 0) << "corners away from the scaled positions";
}

TEST(Refine, IsScaleInvariant) {
  // Scaling by a decimal factor rounds the coordinates, so edges of exactly equal length become
  // unequal by an ulp; the longest-edge choice (and everything after it) must not notice.
  auto cornell = [](double scale) {
    char spec[64];
    std::snprintf(spec, sizeof spec, "builtin:cornell?scale=%.17g", scale);
    return loadScene(spec);
  };
  auto box = [](double scale) { return testing::closedBox(0.5, 1.0, scale); };
  for (const auto& [name, load] :
       {std::pair<std::string, std::function<Mesh(double)>>{"cornell", cornell}, {"box", box}}) {
    const Mesh reference = load(1.0);
    const std::vector<double> scales = {1e-4, 1e4, 0.3, 1e-3, 7.0};
    for (double maxArea : {reference.totalArea() / 4000, reference.totalArea() / 700}) {
      const Mesh patches = refine(reference, maxArea);
      const Mesh ordered = orderAlongCurve(patches);
      for (double scale : scales) {
        SCOPED_TRACE(name + ", max area " + std::to_string(maxArea) + ", scale " +
                     std::to_string(scale));
        const Mesh scaled = refine(load(scale), maxArea * scale * scale);
        expectScaledCopy(patches, scaled, scale);
        expectScaledCopy(ordered, orderAlongCurve(scaled), scale);
      }
    }
    // 96 and 192: on the box, the bound A / target equals the area of the patches of a round.
    for (int64_t target : {96, 192, 3000}) {
      const Mesh counted = refineToCount(reference, target);
      for (double scale : scales) {
        SCOPED_TRACE(name + ", target " + std::to_string(target) + ", scale " +
                     std::to_string(scale));
        expectScaledCopy(counted, refineToCount(load(scale), target), scale);
      }
    }
  }
}

TEST(Blocks, CoverEveryIdOnceWithEqualCounts) {
  for (int64_t count : {0, 1, 7, 100, 1001}) {
    for (int ranks : {1, 2, 3, 7}) {
      int64_t next = 0;
      for (int r = 0; r < ranks; ++r) {
        PatchRange block = blockOf(count, r, ranks);
        EXPECT_EQ(block.begin, next);
        EXPECT_LE(block.size(), count / ranks + 1);
        EXPECT_GE(block.size(), count / ranks);
        for (int64_t id = block.begin; id < block.end; ++id)
          EXPECT_EQ(ownerOf(id, count, ranks), r);
        next = block.end;
      }
      EXPECT_EQ(next, count);
    }
  }
}

}  // namespace
}  // namespace radiosity::partition
