#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <stdexcept>
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

TEST(Refine, SplitsNeedlesWhateverTheirArea) {
  // A needle 10 long and 0.01 wide (area 0.05) under an area bound of 0.1: a patch that long would
  // average B over its whole length, so it is split until its longest edge² ≤ 8 × the bound.
  Mesh needle;
  needle.vertices = {{0, 0, 0}, {10, 0, 0}, {5, 0.01, 0}};
  needle.triangles = {{0, 1, 2}};
  needle.sourceFace = {0};
  needle.reflectance = {{0.5, 0.5, 0.5}};
  needle.emission = {{0, 0, 0}};
  const Mesh patches = refine(needle, 0.1);
  EXPECT_GT(patches.triangleCount(), 8);
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = patches.corner(t, (k + 1) % 3) - patches.corner(t, k);
      EXPECT_LE(dot(d, d), 8 * 0.1) << "patch " << t;
    }
  }
  EXPECT_NEAR(patches.totalArea(), 0.05, 1e-12);
  // Well-shaped triangles meet the area bound first: halves of squares are split by area alone,
  // each of the box's 12 triangles (area 0.5) into 64 of area 1/128.
  EXPECT_EQ(refine(testing::closedBox(0.5, 1.0), 0.01).triangleCount(), 12 * 64);
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

// Adaptive refinement: the marked patches are quartered (two bisections), their neighbours split
// only as far as conformity needs; the box stays watertight, the area is kept, and each new
// patch lies inside the patch its parentOf names, with that patch's material and source face.
TEST(RefineMarked, QuartersTheMarkedPatchesConformingly) {
  const Mesh box = refine(testing::closedBox(0.5, 1.0), 0.05);
  const std::vector<int64_t> marked = {5, 17, 40};
  std::vector<int64_t> parentOf;
  const Mesh refined = refineMarked(box, marked, 2, int64_t{1} << 40, &parentOf);
  for (const auto& [edge, count] : edgeUse(refined))
    ASSERT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
  EXPECT_NEAR(refined.totalArea(), box.totalArea(), 1e-12);
  ASSERT_EQ(static_cast<int64_t>(parentOf.size()), refined.triangleCount());
  EXPECT_TRUE(std::is_sorted(parentOf.begin(), parentOf.end()));  // children in their place
  std::vector<double> childArea(box.triangleCount(), 0);
  for (int64_t t = 0; t < refined.triangleCount(); ++t) {
    const int64_t p = parentOf[t];
    ASSERT_GE(p, 0);
    ASSERT_LT(p, box.triangleCount());
    childArea[p] += refined.area(t);
    EXPECT_EQ(refined.sourceFace[t], box.sourceFace[p]);
    EXPECT_EQ(refined.reflectance[t], box.reflectance[p]);
    EXPECT_GT(dot(refined.normal(t), box.normal(p)), 1 - 1e-12);  // winding kept
  }
  for (int64_t p = 0; p < box.triangleCount(); ++p) {
    EXPECT_NEAR(childArea[p], box.area(p), 1e-14) << p;
    const bool isMarked = std::find(marked.begin(), marked.end(), p) != marked.end();
    const auto children = std::count(parentOf.begin(), parentOf.end(), p);
    if (isMarked) {
      EXPECT_GE(children, 4) << p;  // quartered, or more by closure
    }
  }
  // A patch left whole keeps its corners; those before the first split keep their ids too.
  for (int64_t t = 0; t < refined.triangleCount(); ++t) {
    if (std::count(parentOf.begin(), parentOf.end(), parentOf[t]) == 1) {
      EXPECT_EQ(refined.triangles[t], box.triangles[parentOf[t]]);
    }
  }
  EXPECT_EQ(refined.triangles[0], box.triangles[0]);
  // Few patches beyond the marked ones are split: a conforming closure, not a uniform round.
  EXPECT_LT(refined.triangleCount(), box.triangleCount() + 40);
  // The same marks give the same mesh; the budget stops the splitting.
  EXPECT_EQ(refineMarked(box, marked, 2, int64_t{1} << 40).triangles, refined.triangles);
  EXPECT_LE(refineMarked(box, marked, 2, box.triangleCount() + 2).triangleCount(),
            box.triangleCount() + 2 + 4);
}

TEST(MarkLargestErrors, TakesWholeClassesOfTheLargestErrorsUpToTheShare) {
  // Errors 1000 (twice), 990 (same class as 1000), 500, 100, 10, 0.
  const std::vector<int64_t> error = {10, 1000, 0, 500, 990, 100, 1000};
  // Half of 3600 is held by the class of 1000: all three of them, by id.
  EXPECT_EQ(markLargestErrors(error, 0.5, 100), (std::vector<int64_t>{1, 4, 6}));
  EXPECT_EQ(markLargestErrors(error, 0.9, 100), (std::vector<int64_t>{1, 4, 6, 3}));
  EXPECT_EQ(markLargestErrors(error, 1.0, 100), (std::vector<int64_t>{1, 4, 6, 3, 5, 0}));
  EXPECT_EQ(markLargestErrors(error, 1.0, 2), (std::vector<int64_t>{1, 4}));
  EXPECT_TRUE(markLargestErrors(std::vector<int64_t>(5, 0), 0.5, 100).empty());
  // At least minMarks (whole classes; none without an error), still at most maxMarks.
  EXPECT_EQ(markLargestErrors(error, 0.5, 100, 4), (std::vector<int64_t>{1, 4, 6, 3}));
  EXPECT_EQ(markLargestErrors(error, 0.5, 100, 99), (std::vector<int64_t>{1, 4, 6, 3, 5, 0}));
  EXPECT_EQ(markLargestErrors(error, 0.5, 2, 4), (std::vector<int64_t>{1, 4}));
  // An error that changes by round-off within its class changes nothing.
  std::vector<int64_t> nudged = error;
  nudged[4] = 991;
  EXPECT_EQ(markLargestErrors(nudged, 0.5, 100), markLargestErrors(error, 0.5, 100));
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

// Checks the shape every split must have: ranks + 1 boundaries from 0 to count, nondecreasing
// (contiguous blocks in rank order), and owner() the inverse of of().
void expectContiguousCover(const Blocks& blocks, int64_t count, int ranks) {
  ASSERT_EQ(blocks.ranks(), ranks);
  ASSERT_EQ(blocks.count(), count);
  int64_t next = 0;
  for (int r = 0; r < ranks; ++r) {
    const PatchRange block = blocks.of(r);
    ASSERT_EQ(block.begin, next) << "rank " << r;
    ASSERT_GE(block.end, block.begin) << "rank " << r;
    for (int64_t id = block.begin; id < block.end; ++id) ASSERT_EQ(blocks.owner(id), r);
    next = block.end;
  }
  EXPECT_EQ(next, count);
}

TEST(Blocks, ByCountAreTheBlocksOfBlockOf) {
  for (int64_t count : {0, 1, 7, 100, 1001}) {
    for (int ranks : {1, 2, 3, 7}) {
      const Blocks blocks = Blocks::byCount(count, ranks);
      expectContiguousCover(blocks, count, ranks);
      for (int r = 0; r < ranks; ++r) {
        EXPECT_EQ(blocks.of(r).begin, blockOf(count, r, ranks).begin);
        EXPECT_EQ(blocks.of(r).end, blockOf(count, r, ranks).end);
      }
    }
  }
}

// A known cost curve: cheap patches, then a stretch 20 times dearer, then a gentle ramp. Each
// block's cost must be within the dearest single patch of the mean (the boundary is the patch
// edge nearest its target), and the blocks by count must be far off, or the test shows nothing.
TEST(Blocks, ByCostEvensTheCostWithinOnePatchOfTheMean) {
  const int64_t count = 10000;
  std::vector<double> cost(count);
  for (int64_t i = 0; i < count; ++i)
    cost[i] = i < 3000 ? 1.0 : (i < 4000 ? 20.0 : 1.0 + 4.0 * (i - 4000) / 6000.0);
  const double dearest = *std::max_element(cost.begin(), cost.end());
  double total = 0;
  for (double c : cost) total += c;
  auto blockCost = [&](PatchRange block) {
    double sum = 0;
    for (int64_t i = block.begin; i < block.end; ++i) sum += cost[i];
    return sum;
  };
  for (int ranks : {2, 3, 8, 64}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const Blocks blocks = Blocks::byCost(cost, ranks);
    expectContiguousCover(blocks, count, ranks);
    const double mean = total / ranks;
    double worstByCount = 0;
    for (int r = 0; r < ranks; ++r) {
      EXPECT_LE(std::fabs(blockCost(blocks.of(r)) - mean), dearest + 1e-9) << "rank " << r;
      worstByCount = std::max(worstByCount, blockCost(blockOf(count, r, ranks)) / mean);
    }
    EXPECT_GT(worstByCount, 1.15);
  }
}

// The cost given per run of patches (as the pilot gives it) cuts where the same cost given per
// patch does, and a cut may fall inside a run.
TEST(Blocks, ByCostOfRunsCutsAsByCostOfPatches) {
  const std::vector<int64_t> runStart = {0, 10, 10, 250, 400, 1000};  // one run is empty
  const std::vector<double> perPatch = {5.0, 7.0, 0.5, 3.0, 1.0};
  std::vector<double> cost;
  for (size_t s = 0; s < perPatch.size(); ++s)
    for (int64_t i = runStart[s]; i < runStart[s + 1]; ++i) cost.push_back(perPatch[s]);
  for (int ranks : {1, 2, 5, 13}) {
    const Blocks runs = Blocks::byCost(runStart, perPatch, ranks);
    expectContiguousCover(runs, 1000, ranks);
    EXPECT_EQ(runs.boundaries(), Blocks::byCost(cost, ranks).boundaries()) << ranks << " ranks";
  }
}

// More ranks than patches: some blocks are empty, every patch still has one owner; the same when
// one patch carries nearly all the cost.
TEST(Blocks, ByCostLeavesRanksEmptyWhenThereIsTooLittleToShare) {
  const std::vector<double> few = {1.0, 2.0, 3.0};
  const Blocks blocks = Blocks::byCost(few, 7);
  expectContiguousCover(blocks, 3, 7);
  int empty = 0;
  for (int r = 0; r < 7; ++r) empty += blocks.of(r).size() == 0;
  EXPECT_EQ(empty, 4);
  std::vector<double> lopsided(100, 1e-6);
  lopsided[40] = 1.0;
  expectContiguousCover(Blocks::byCost(lopsided, 4), 100, 4);
  expectContiguousCover(Blocks::byCost(std::vector<double>(), 3), 0, 3);
}

// No usable cost (all zero, or not finite): blocks by count, never a failure.
TEST(Blocks, ByCostWithoutAUsableCostFallsBackToCounts) {
  const int64_t count = 101;
  for (double value : {0.0, std::nan(""), HUGE_VAL}) {
    const std::vector<double> cost(count, value);
    EXPECT_EQ(Blocks::byCost(cost, 4).boundaries(), Blocks::byCount(count, 4).boundaries())
        << value;
  }
}

TEST(Blocks, RefuseBoundariesThatAreNotContiguousBlocks) {
  EXPECT_THROW(Blocks(std::vector<int64_t>{0, 5, 3}), std::invalid_argument);
  EXPECT_THROW(Blocks(std::vector<int64_t>{1, 5}), std::invalid_argument);
  EXPECT_THROW(Blocks(std::vector<int64_t>{0}), std::invalid_argument);
}

}  // namespace
}  // namespace radiosity::partition
