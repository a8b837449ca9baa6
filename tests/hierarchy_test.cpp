// The patch tree and its links (hierarchy/): the tree is a function of the mesh alone, its nodes
// are ranges of the curve whose figures hold every patch under them, the links tile every pair
// of patches exactly once, and push and pull move light as their definitions say.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "hierarchy/hierarchy.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::hierarchy {
namespace {

Mesh cornell(double maxArea) {
  return partition::orderAlongCurve(partition::refine(loadScene("builtin:cornell"), maxArea));
}

// Every node is the union of its two children, which split it where the curve keys' highest
// differing bit flips; every patch has one leaf; the root holds all.
TEST(PatchTree, NodesAreRangesSplitAtCubesOfTheCurve) {
  const Mesh patches = cornell(4000);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  ASSERT_EQ(tree.nodeCount(), 2 * n - 1);
  ASSERT_EQ(tree.innerCount(), n - 1);
  EXPECT_EQ(tree.node(tree.root()).begin, 0);
  EXPECT_EQ(tree.node(tree.root()).end, n);
  const std::vector<uint64_t> keys = partition::curveKeys(patches);
  std::vector<int> reached(static_cast<size_t>(tree.nodeCount()), 0);
  for (int64_t id = 0; id < tree.innerCount(); ++id) {
    const ClusterNode node = tree.node(id);
    const ClusterNode a = tree.node(node.child[0]), b = tree.node(node.child[1]);
    for (int64_t child : node.child) ++reached[child];
    EXPECT_EQ(a.begin, node.begin);
    EXPECT_EQ(a.end, b.begin);
    EXPECT_EQ(b.end, node.end);
    for (int64_t child : node.child) {
      EXPECT_GT(child, id);  // children follow their parent
      if (tree.isLeaf(child)) {
        EXPECT_EQ(child, tree.leafOf(tree.node(child).begin));
      }
    }
    for (int64_t p = node.begin; p < node.end; ++p)
      EXPECT_EQ(tree.childHolding(id, p), p < a.end ? node.child[0] : node.child[1]);
    if (keys[node.begin] == keys[node.end - 1]) continue;
    // The two halves differ in the highest bit where the node's keys differ, and agree above.
    const uint64_t differ = keys[node.begin] ^ keys[node.end - 1];
    const uint64_t bit = uint64_t{1} << (63 - std::countl_zero(differ));
    for (int64_t p = a.begin; p < a.end; ++p) EXPECT_EQ(keys[p] & bit, 0U);
    for (int64_t p = b.begin; p < b.end; ++p) EXPECT_NE(keys[p] & bit, 0U);
  }
  for (int64_t id = 1; id < tree.nodeCount(); ++id) EXPECT_EQ(reached[id], 1) << id;
}

// Each node's area is its patches' sum, its centroid their area-weighted mean, its sphere holds
// every corner and its cone every normal (rounded outwards into floats); its face is theirs if
// they have one.
TEST(PatchTree, FiguresHoldEveryPatchUnderTheNode) {
  const Mesh patches = cornell(400);
  const PatchTree tree(patches);
  for (int64_t id = 0; id < tree.nodeCount(); ++id) {
    const ClusterNode node = tree.node(id);
    double area = 0;
    Vec3 moment{};
    for (int64_t p = node.begin; p < node.end; ++p) {
      area += patches.area(p);
      moment = moment + patches.area(p) * patches.centroid(p);
    }
    EXPECT_NEAR(node.area, area, 1e-12 * area);
    bool oneFace = true;
    for (int64_t p = node.begin; p < node.end; ++p)
      oneFace = oneFace && patches.sourceFace[p] == patches.sourceFace[node.begin];
    EXPECT_EQ(node.face, oneFace ? patches.sourceFace[node.begin] : -1);
    // (the centroid is kept in floats, each level from its children's: to 1e-6 of the size)
    EXPECT_LT(length(node.centroid - (1.0 / area) * moment), 1e-6 * 560);
    for (int64_t p = node.begin; p < node.end; ++p) {
      for (int k = 0; k < 3; ++k)
        EXPECT_LE(length(patches.corner(p, k) - node.centroid), node.radius);
      if (node.cone < 3.14159) {
        const Vec3 normal = patches.normal(p);
        EXPECT_LE(std::atan2(length(cross(normal, node.normal)), dot(normal, node.normal)),
                  node.cone);
      }
    }
  }
}

// Uniform: one material under the node. The Cornell box's light is its own material, so no
// node holding the light and the ceiling around it is uniform.
TEST(PatchTree, UniformNodesHoldOneMaterial) {
  const Mesh patches = cornell(400);
  const PatchTree tree(patches);
  int uniform = 0;
  for (int64_t id = 0; id < tree.nodeCount(); ++id) {
    const ClusterNode node = tree.node(id);
    bool alike = true;
    for (int64_t p = node.begin + 1; p < node.end; ++p)
      alike = alike && patches.reflectance[p] == patches.reflectance[node.begin] &&
              patches.emission[p] == patches.emission[node.begin];
    EXPECT_EQ(node.uniform, alike) << node.begin << ".." << node.end;
    uniform += node.uniform && !node.isLeaf();
  }
  EXPECT_GT(uniform, 0);
}

// In any other order than the curve's the nodes split in the middle: still every patch once.
TEST(PatchTree, PatchesOffTheCurveSplitInTheMiddle) {
  const Mesh patches = partition::refine(loadScene("builtin:cornell"), 4000);  // not reordered
  const PatchTree tree(patches);
  ASSERT_EQ(tree.nodeCount(), 2 * patches.triangleCount() - 1);
  for (int64_t id = 0; id < tree.innerCount(); ++id) {
    const ClusterNode node = tree.node(id);
    EXPECT_EQ(tree.node(node.child[0]).size(), node.size() / 2);
  }
}

// The tree is made from the mesh alone: twice the same, on any rank count.
TEST(PatchTree, SameTreeFromTheSameMesh) {
  const Mesh patches = cornell(4000);
  const PatchTree a(patches), b(patches);
  ASSERT_EQ(a.nodeCount(), b.nodeCount());
  for (int64_t id = 0; id < a.nodeCount(); ++id) {
    EXPECT_EQ(a.node(id).begin, b.node(id).begin);
    EXPECT_EQ(a.node(id).end, b.node(id).end);
    EXPECT_EQ(a.node(id).area, b.node(id).area);
  }
}

// Every pair (i, j) of patches falls in exactly one link: the links the pairs choose do not
// overlap and together hold n² pairs.
TEST(Links, LinksTileEveryPairOnce) {
  const Mesh patches = cornell(8000);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  for (const bool patchReceivers : {false, true}) {
    LinkOracle oracle;
    oracle.spread = 0.5;
    oracle.patchReceivers = patchReceivers;
    std::set<std::pair<int64_t, int64_t>> links;
    for (int64_t i = 0; i < n; ++i)
      for (int64_t j = 0; j < n; ++j) {
        const auto [r, s] = linkOf(tree, oracle, i, j);
        ASSERT_TRUE(tree.node(r).holds(i) && tree.node(s).holds(j));
        if (patchReceivers) {
          ASSERT_TRUE(tree.isLeaf(r));
        }
        links.insert({r, s});
      }
    int64_t pairs = 0;
    for (const auto& [r, s] : links) pairs += tree.node(r).size() * tree.node(s).size();
    EXPECT_EQ(pairs, n * n);
    EXPECT_LT(static_cast<int64_t>(links.size()), n * n);  // some pairs were grouped
  }
}

// The tally's walks, each going on from the one before, choose the links a walk from the root
// (linkOf) does, and each link's factor is the area-weighted mean of its hits: every row hitting
// every patch with the sum 1 gives F_RS = |S| / samples.
TEST(Links, TallyChoosesLinkOfsLinks) {
  const Mesh patches = cornell(8000);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  LinkOracle oracle;
  oracle.spread = 0.5;
  oracle.seesWhole = [](const ClusterNode& r, const ClusterNode& s) {
    return (r.begin + s.end) % 3 != 0;  // some receivers split further, as by probes
  };
  SampleTally rows;
  rows.samples = 1;
  for (int64_t i = 0; i < n; ++i) {
    for (int64_t j = 0; j < n; ++j) {
      rows.column.push_back(j);
      rows.sum.push_back(int64_t{1} << 32);
    }
    rows.rowStart.push_back(static_cast<int64_t>(rows.column.size()));
  }
  const Links links = linksFromRows(tree, oracle, rows);
  std::map<std::pair<int64_t, int64_t>, double> expected;
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = 0; j < n; ++j) expected[linkOf(tree, oracle, i, j)] = 0;
  ASSERT_EQ(links.size(), static_cast<int64_t>(expected.size()));
  for (int64_t k = 0; k < links.size(); ++k) {
    ASSERT_TRUE(expected.count({links.receiver[k], links.source[k]}));
    EXPECT_NEAR(links.factor[k], static_cast<double>(tree.node(links.source[k]).size()), 1e-9);
  }
}

// Pull is the area-weighted mean; transport pushes a node's gathered light to every patch under
// it: with one link root → root of factor f, every patch gathers f times the area-mean B.
TEST(Links, PullMeansAndPushToEveryPatch) {
  const Mesh patches = cornell(4000);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  std::vector<double> b(n);
  double power = 0, area = 0;
  for (int64_t p = 0; p < n; ++p) {
    b[p] = 1.0 + static_cast<double>(p % 7);
    power += patches.area(p) * b[p];
    area += patches.area(p);
  }
  EXPECT_NEAR(pullMeans(tree, b)[tree.root()], power / area, 1e-12 * power / area);
  Links links;
  links.receiver = {tree.root()};
  links.source = {tree.root()};
  links.factor = {0.25};
  for (double h : transport(tree, links, b)) EXPECT_NEAR(h, 0.25 * power / area, 1e-12);
}

// Linear push keeps the power the links carry (the children's values average to the parent's)
// and gives more light to the patches nearer a source: a floor under a lamp on one side.
TEST(Links, LinearPushKeepsPowerAndLeansTowardsTheSource) {
  Mesh scene;
  testing::addSubdividedQuad(scene, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 8, {0.5, 0.5, 0.5},
                             {0, 0, 0});  // the floor, facing +z
  testing::addQuad(scene, {3, 0.4, 1}, {3, 0.6, 1}, {3.2, 0.6, 1}, {3.2, 0.4, 1}, {0, 0, 0},
                   {1, 1, 1});  // a small lamp off to +x, facing down
  const Mesh patches = partition::orderAlongCurve(scene);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  // One link from the lamp's node to the floor's: the largest nodes of each alone.
  int64_t floor = -1, lamp = -1;
  for (int64_t id = 0; id < tree.nodeCount(); ++id) {
    const ClusterNode node = tree.node(id);
    bool allFloor = true, allLamp = true;
    for (int64_t p = node.begin; p < node.end; ++p) {
      allFloor = allFloor && patches.emission[p][0] == 0;
      allLamp = allLamp && patches.emission[p][0] > 0;
    }
    if (allFloor && (floor < 0 || node.size() > tree.node(floor).size())) floor = id;
    if (allLamp && (lamp < 0 || node.size() > tree.node(lamp).size())) lamp = id;
  }
  ASSERT_EQ(tree.node(floor).size(), 128);
  Links links;
  links.receiver = {floor};
  links.source = {lamp};
  links.factor = {0.01};
  std::vector<double> b(n);
  for (int64_t p = 0; p < n; ++p) b[p] = patches.emission[p][0];
  const std::vector<double> uniform = transport(tree, links, b, Push::kUniform);
  const std::vector<double> linear = transport(tree, links, b, Push::kLinear);
  double uniformPower = 0, linearPower = 0, nearer = 0, farther = 0;
  for (int64_t p = 0; p < n; ++p) {
    uniformPower += patches.area(p) * uniform[p];
    linearPower += patches.area(p) * linear[p];
    if (patches.emission[p][0] > 0) continue;
    EXPECT_GT(linear[p], 0);
    (patches.centroid(p).x > 0.5 ? nearer : farther) += linear[p];
  }
  EXPECT_NEAR(linearPower, uniformPower, 1e-12 * uniformPower);
  EXPECT_GT(nearer, 1.2 * farther);
}

// The visibility callback is asked only of receiver clusters that pass the rest, and a "no" sends
// the walk down to smaller receivers: with it always "no", every receiver is a patch.
TEST(Links, ReceiversAreGroupedOnlyWhereTheSourceIsSeenWhole) {
  const Mesh patches = cornell(8000);
  const PatchTree tree(patches);
  const int64_t n = patches.triangleCount();
  LinkOracle oracle;
  oracle.spread = 0.5;
  int64_t asked = 0;
  oracle.seesWhole = [&](const ClusterNode& receiver, const ClusterNode& source) {
    ++asked;
    EXPECT_FALSE(receiver.isLeaf());
    EXPECT_TRUE(source.uniform);
    return false;
  };
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = 0; j < n; ++j) {
      const auto [r, s] = linkOf(tree, oracle, i, j);
      ASSERT_TRUE(tree.isLeaf(r)) << i << " " << j;
      ASSERT_TRUE(tree.node(s).holds(j));
    }
  EXPECT_GT(asked, 0);
}

}  // namespace
}  // namespace radiosity::hierarchy
