// Coarsening (partition::undoBisections): what refinement split is merged back exactly, the mesh
// stays conforming and keeps its area, faces and winding, and only true bisections are undone.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::partition {
namespace {

// How many triangles use each undirected edge.
std::map<std::pair<int64_t, int64_t>, int> edgeUse(const Mesh& mesh) {
  std::map<std::pair<int64_t, int64_t>, int> use;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = t[k], b = t[(k + 1) % 3];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  return use;
}

// The triangle's corners as points, turned so that the smallest comes first (a triangle merged
// back may start at another corner than the one it was split from).
std::array<Vec3, 3> cornersOf(const Mesh& mesh, int64_t t) {
  std::array<Vec3, 3> p{mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)};
  const auto less = [](const Vec3& a, const Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  };
  std::rotate(p.begin(), std::min_element(p.begin(), p.end(), less), p.end());
  return p;
}

std::vector<int64_t> verticesOf(const std::vector<Bisection>& bisections) {
  std::vector<int64_t> v;
  for (const Bisection& b : bisections) v.push_back(b.vertex);
  return v;
}

// Refining every patch of a closed box once more and undoing every bisection that made gives the
// box back: the same triangles (up to where each starts), in the same order, the same vertices.
TEST(UndoBisections, GiveBackTheMeshARoundSplit) {
  const Mesh box = refine(testing::closedBox(0.5, 1.0), 0.05);
  std::vector<int64_t> all(box.triangleCount());
  std::iota(all.begin(), all.end(), 0);
  const Mesh refined = refineMarked(box, all, 1, int64_t{1} << 40);
  ASSERT_EQ(refined.triangleCount(), 2 * box.triangleCount());
  // The new midpoints are what can be undone (the box's own vertices are corners of 8).
  const std::vector<Bisection> found = undoableBisections(refined);
  ASSERT_EQ(static_cast<int64_t>(found.size()), box.triangleCount() / 2);
  for (const Bisection& b : found) EXPECT_GE(b.vertex, static_cast<int64_t>(box.vertices.size()));
  std::vector<std::array<int64_t, 2>> halvesOf;
  const Mesh back = undoBisections(refined, verticesOf(found), &halvesOf);
  ASSERT_EQ(back.triangleCount(), box.triangleCount());
  EXPECT_EQ(back.vertices, box.vertices);
  ASSERT_EQ(static_cast<int64_t>(halvesOf.size()), back.triangleCount());
  for (int64_t t = 0; t < box.triangleCount(); ++t) {
    EXPECT_EQ(cornersOf(back, t), cornersOf(box, t)) << t;
    EXPECT_GT(dot(back.normal(t), box.normal(t)), 1 - 1e-12);  // the winding kept
    EXPECT_EQ(back.sourceFace[t], box.sourceFace[t]);
    EXPECT_EQ(back.reflectance[t], box.reflectance[t]);
    EXPECT_EQ(back.emission[t], box.emission[t]);
    // Each from the two halves split from it, which lie in its place in the refined order.
    EXPECT_EQ(halvesOf[t], (std::array<int64_t, 2>{2 * t, 2 * t + 1}));
  }
}

// Undoing some of them: conforming (every edge of the closed box used twice), the area and the
// faces kept, each merged triangle the union of its halves, the rest untouched and in order.
TEST(UndoBisections, KeepTheMeshConformingAndItsArea) {
  const Mesh box = refine(testing::closedBox(0.5, 1.0), 0.05);
  const Mesh refined = refineMarked(box, {3, 11, 12, 30, 31}, 2, int64_t{1} << 40);
  const std::vector<Bisection> found = undoableBisections(refined);
  ASSERT_GE(found.size(), 10u);
  std::vector<int64_t> some;
  std::vector<char> used(refined.triangleCount(), 0);
  for (size_t i = 0; i < found.size(); i += 2) some.push_back(found[i].vertex);
  std::vector<std::array<int64_t, 2>> halvesOf;
  const Mesh merged = undoBisections(refined, some, &halvesOf);
  EXPECT_LT(merged.triangleCount(), refined.triangleCount());
  for (const auto& [edge, count] : edgeUse(merged))
    ASSERT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
  EXPECT_NEAR(merged.totalArea(), refined.totalArea(), 1e-12);
  EXPECT_EQ(merged.vertices.size(), refined.vertices.size() - some.size());
  for (int64_t t = 0; t < merged.triangleCount(); ++t) {
    const auto [first, second] = halvesOf[t];
    if (t > 0) {
      EXPECT_GT(first, halvesOf[t - 1][0]);  // in order
    }
    ++used[first];
    EXPECT_EQ(merged.sourceFace[t], refined.sourceFace[first]);
    if (second < 0) {
      EXPECT_EQ(cornersOf(merged, t), cornersOf(refined, first));
      continue;
    }
    ++used[second];
    EXPECT_GT(second, first);
    EXPECT_EQ(refined.sourceFace[second], refined.sourceFace[first]);
    EXPECT_NEAR(refined.area(first), refined.area(second), 1e-15);  // halves of equal area
    EXPECT_NEAR(merged.area(t), refined.area(first) + refined.area(second), 1e-15);
    EXPECT_GT(dot(merged.normal(t), refined.normal(first)), 1 - 1e-12);
  }
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](char u) { return u == 1; }));
  // The same vertices give the same mesh, in any order.
  std::vector<int64_t> reversed(some.rbegin(), some.rend());
  EXPECT_EQ(undoBisections(refined, reversed).triangles, merged.triangles);
}

// A scene's own corner, a vertex no bisection made, and two bisections sharing a triangle are
// refused; halves of different materials are no bisection to undo.
TEST(UndoBisections, UndoOnlyWhatRefinementMade) {
  const Mesh box = refine(testing::closedBox(0.5, 1.0), 0.05);
  const Mesh refined = refineMarked(box, {3}, 2, int64_t{1} << 40);
  EXPECT_THROW(undoBisections(refined, {0}), Error);
  EXPECT_THROW(undoBisections(refined, {static_cast<int64_t>(refined.vertices.size())}), Error);
  const std::vector<Bisection> found = undoableBisections(refined);
  ASSERT_FALSE(found.empty());
  EXPECT_THROW(undoBisections(refined, {found[0].vertex, found[0].vertex}), Error);
  Mesh painted = refined;
  for (int64_t t : found[0].halves)
    if (t >= 0) {
      painted.reflectance[t] = {0.9, 0.1, 0.1};
      break;
    }
  const std::vector<Bisection> left = undoableBisections(painted);
  EXPECT_EQ(left.size(), found.size() - 1);
  EXPECT_THROW(undoBisections(painted, {found[0].vertex}), Error);
}

TEST(MarkFlatBisections, TakesTheLeastErrorFirstWithinTheBudget) {
  // Four stars of two halves each: errors 0 + 0, 10 + 10, 100 + 90 (as in one class) and
  // 100 + 100, the last not mergeable (a half split this round).
  std::vector<Bisection> stars(4);
  const std::vector<int64_t> error = {0, 0, 10, 10, 100, 90, 100, 100};
  std::vector<char> mergeable(8, 1);
  mergeable[7] = 0;
  for (int s = 0; s < 4; ++s) stars[s] = {40 + s, {0, 1}, {2 * s, 2 * s + 1, -1, -1}};
  EXPECT_EQ(markFlatBisections(stars, error, mergeable, 0), (std::vector<int64_t>{40}));
  EXPECT_EQ(markFlatBisections(stars, error, mergeable, 20), (std::vector<int64_t>{40, 41}));
  EXPECT_EQ(markFlatBisections(stars, error, mergeable, 209), (std::vector<int64_t>{40, 41}));
  EXPECT_EQ(markFlatBisections(stars, error, mergeable, 1e9), (std::vector<int64_t>{40, 41, 42}));
}

}  // namespace
}  // namespace radiosity::partition
