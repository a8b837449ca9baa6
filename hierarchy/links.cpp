// Links between nodes of the patch tree (links.h).
#include "hierarchy/links.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radiosity::hierarchy {

bool admissible(const ClusterNode& receiver, const ClusterNode& source, const LinkOracle& oracle) {
  if (receiver.isLeaf() && source.isLeaf()) return true;
  if (receiver.holds(source.begin) || source.holds(receiver.begin)) return false;
  if (receiver.cone > oracle.cone || source.cone > oracle.cone) return false;
  if (!source.uniform) return false;
  if (oracle.patchReceiversOfEmitters && !receiver.isLeaf() && source.emits) return false;
  if (oracle.receiversWithinFace && !receiver.isLeaf() && receiver.face < 0) return false;
  const double distance = length(receiver.centroid - source.centroid);
  if (receiver.radius + source.radius >= oracle.spread * distance) return false;
  return receiver.isLeaf() || !oracle.seesWhole || oracle.seesWhole(receiver, source);
}

std::pair<int64_t, int64_t> linkOf(const PatchTree& tree, const LinkOracle& oracle, int64_t i,
                                   int64_t j) {
  int64_t r = oracle.patchReceivers ? tree.leafOf(i) : tree.root(), s = tree.root();
  for (;;) {
    const ClusterNode receiver = tree.node(r);
    const ClusterNode source = tree.node(s);
    if (admissible(receiver, source, oracle)) return {r, s};
    const bool splitReceiver =
        !receiver.isLeaf() && (source.isLeaf() || receiver.radius >= source.radius);
    if (splitReceiver)
      r = tree.childHolding(r, i);
    else
      s = tree.childHolding(s, j);
  }
}

void LinkTally::add(const SampleTally& piece) {
  const auto nodeCount = static_cast<uint64_t>(tree_.nodeCount());
  const double unit = 0x1p32 * static_cast<double>(piece.samples);
  for (int64_t row = 0; row < piece.rowCount(); ++row) {
    const int64_t i = piece.firstRow + row;
    const double area = tree_.area(tree_.leafOf(i));
    for (int64_t k = piece.rowStart[row]; k < piece.rowStart[row + 1]; ++k) {
      const auto [r, s] = linkOf(tree_, oracle_, i, piece.column[k]);
      sums_[static_cast<uint64_t>(r) * nodeCount + static_cast<uint64_t>(s)] +=
          area * (static_cast<double>(piece.sum[k]) / unit);
    }
  }
}

Links LinkTally::links() const {
  const auto nodeCount = static_cast<uint64_t>(tree_.nodeCount());
  std::vector<std::pair<uint64_t, double>> sorted(sums_.begin(), sums_.end());
  std::sort(sorted.begin(), sorted.end());
  Links links;
  links.receiver.reserve(sorted.size());
  links.source.reserve(sorted.size());
  links.factor.reserve(sorted.size());
  for (const auto& [key, sum] : sorted) {
    const auto r = static_cast<int64_t>(key / nodeCount);
    links.receiver.push_back(r);
    links.source.push_back(static_cast<int64_t>(key % nodeCount));
    links.factor.push_back(sum / tree_.area(r));
  }
  return links;
}

Links linksFromRows(const PatchTree& tree, const LinkOracle& oracle, const SampleTally& tally) {
  LinkTally links(tree, oracle);
  links.add(tally);
  return links.links();
}

std::vector<double> pullMeans(const PatchTree& tree, const std::vector<double>& value) {
  std::vector<double> mean(static_cast<size_t>(tree.nodeCount()), 0.0);
  for (int64_t p = 0; p < tree.patchCount(); ++p) mean[tree.leafOf(p)] = value[p];
  // Inner children follow their parent: from the back, every child is done before its parent.
  for (int64_t id = tree.innerCount() - 1; id >= 0; --id) {
    const auto [a, b] = tree.children(id);
    const double area = tree.area(id);
    mean[id] = area > 0 ? (tree.area(a) * mean[a] + tree.area(b) * mean[b]) / area : 0.0;
  }
  return mean;
}

namespace {

// ∇ log(cosθ_R cosθ_S / d²) as the receiving point moves from the receiver's centroid: how the
// point kernel from `source` varies over `receiver` (0 where either faces away at the centroids).
Vec3 kernelGradient(const ClusterNode& receiver, const ClusterNode& source) {
  const Vec3 v = source.centroid - receiver.centroid;
  const double d2 = dot(v, v), towards = dot(receiver.normal, v), back = -dot(source.normal, v);
  if (towards <= 0 || back <= 0 || d2 <= 0) return Vec3{};
  Vec3 g = (-1.0 / towards) * receiver.normal + (1.0 / back) * source.normal + (4.0 / d2) * v;
  g = g - dot(g, receiver.normal) * receiver.normal;  // along the receiver's plane
  // No patch of the receiver gets less than half the mean or more than 1.5 times it.
  const double reach = length(g) * receiver.radius;
  return reach > 0.5 ? (0.5 / reach) * g : g;
}

}  // namespace

std::vector<double> transport(const PatchTree& tree, const Links& links,
                              const std::vector<double>& radiosity, Push push) {
  const std::vector<double> mean = pullMeans(tree, radiosity);
  const auto nodes = static_cast<size_t>(tree.nodeCount());
  std::vector<double> gathered(nodes, 0.0);
  std::vector<Vec3> slope(push == Push::kLinear ? nodes : 0);
  for (int64_t k = 0; k < links.size(); ++k) {
    const double light = links.factor[k] * mean[links.source[k]];
    const int64_t r = links.receiver[k];
    gathered[r] += light;
    if (push == Push::kLinear && !tree.isLeaf(r))
      slope[r] = slope[r] + light * kernelGradient(tree.node(r), tree.node(links.source[k]));
  }
  // Push: a parent before its children; a linear node's light at each child's centroid (the
  // area-weighted mean of the children's values is the parent's: power is kept).
  for (int64_t id = 0; id < tree.innerCount(); ++id) {
    const Vec3 centre = push == Push::kLinear ? tree.node(id).centroid : Vec3{};
    for (int64_t child : tree.children(id)) {
      gathered[child] += gathered[id];
      if (push == Push::kLinear) {
        gathered[child] += dot(slope[id], tree.node(child).centroid - centre);
        if (!tree.isLeaf(child)) slope[child] = slope[child] + slope[id];
      }
    }
  }
  std::vector<double> irradiance(radiosity.size(), 0.0);
  for (size_t p = 0; p < irradiance.size(); ++p)
    irradiance[p] = gathered[tree.leafOf(static_cast<int64_t>(p))];
  return irradiance;
}

}  // namespace radiosity::hierarchy
