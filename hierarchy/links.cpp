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

namespace {

// The walks for one receiving patch i (linkOf's) from (root, root) down, the larger of the pair
// (by radius) split towards i or j until the pair is admissible or both are patches. Over
// sources j in increasing order each walk goes on from the longest start of the one before whose
// sources still hold j (the steps up to there are the same, since a step depends only on its
// pair), so that sources near each other, as a row's sorted columns are, share most of their
// walk.
class RowWalk {
 public:
  RowWalk(const PatchTree& tree, const LinkOracle& oracle, int64_t i)
      : tree_(tree), oracle_(oracle), i_(i) {}

  std::pair<int64_t, int64_t> linkTo(int64_t j) {
    if (path_.empty()) {
      const int64_t r = oracle_.patchReceivers ? tree_.leafOf(i_) : tree_.root();
      path_.push_back({tree_.node(r), tree_.node(tree_.root()), r, tree_.root()});
    } else {
      const size_t before = path_.size();
      while (path_.size() > 1 && !path_.back().source.holds(j)) path_.pop_back();
      // The last walk's end still holds j: its pair was admitted, so it is j's link too.
      if (path_.size() == before) return {path_.back().r, path_.back().s};
    }
    for (;;) {
      const Step& step = path_.back();
      if (admissible(step.receiver, step.source, oracle_)) return {step.r, step.s};
      const bool splitReceiver =
          !step.receiver.isLeaf() &&
          (step.source.isLeaf() || step.receiver.radius >= step.source.radius);
      const int64_t r = splitReceiver ? tree_.childHolding(step.r, i_) : step.r;
      const int64_t s = splitReceiver ? step.s : tree_.childHolding(step.s, j);
      path_.push_back({splitReceiver ? tree_.node(r) : step.receiver,
                       splitReceiver ? step.source : tree_.node(s), r, s});
    }
  }

 private:
  struct Step {
    ClusterNode receiver, source;
    int64_t r, s;
  };
  const PatchTree& tree_;
  const LinkOracle& oracle_;
  int64_t i_;
  std::vector<Step> path_;
};

}  // namespace

std::pair<int64_t, int64_t> linkOf(const PatchTree& tree, const LinkOracle& oracle, int64_t i,
                                   int64_t j) {
  return RowWalk(tree, oracle, i).linkTo(j);
}

// Sums of the same key added together, in key order.
void LinkTally::sumAlike(std::vector<Sum>& sums) {
  std::stable_sort(sums.begin(), sums.end(),
                   [](const auto& a, const auto& b) { return a.key < b.key; });
  size_t out = 0;
  for (size_t k = 0; k < sums.size(); ++k) {
    if (out > 0 && sums[out - 1].key == sums[k].key)
      sums[out - 1].sum += sums[k].sum;
    else
      sums[out++] = sums[k];
  }
  sums.resize(out);
}

void LinkTally::add(const SampleTally& piece) {
  const auto nodeCount = static_cast<uint64_t>(tree_.nodeCount());
  const double unit = 0x1p32 * static_cast<double>(piece.samples);
  for (int64_t row = 0; row < piece.rowCount(); ++row) {
    const int64_t i = piece.firstRow + row;
    const double area = tree_.area(tree_.leafOf(i));
    RowWalk walk(tree_, oracle_, i);
    // Hits in one link come one after another (the columns are sorted): summed as they come.
    for (int64_t k = piece.rowStart[row]; k < piece.rowStart[row + 1]; ++k) {
      const auto [r, s] = walk.linkTo(piece.column[k]);
      const uint64_t key = static_cast<uint64_t>(r) * nodeCount + static_cast<uint64_t>(s);
      const double value = area * (static_cast<double>(piece.sum[k]) / unit);
      if (k > piece.rowStart[row] && open_.back().key == key)
        open_.back().sum += value;
      else
        open_.push_back({key, value});
    }
  }
  rowsEnd_ = rowsEnd_ >= 0 && piece.firstRow >= rowsEnd_ ? piece.firstRow + piece.rowCount() : -1;
  if (rowsEnd_ < 0 && !complete_.empty()) {  // out of order: a done receiver may get more hits
    open_.insert(open_.end(), complete_.begin(), complete_.end());
    complete_ = {};
  }
  sumAlike(open_);
  if (rowsEnd_ < 0) return;
  // Receivers whose rows all lie before rowsEnd_ get no more hits: their links are done.
  const auto done = std::stable_partition(open_.begin(), open_.end(), [&](const Sum& link) {
    return tree_.end(static_cast<int64_t>(link.key / nodeCount)) > rowsEnd_;
  });
  complete_.insert(complete_.end(), done, open_.end());
  open_.erase(done, open_.end());
}

void LinkTally::forEach(const LinkVisitor& visit) const {
  const auto nodeCount = static_cast<uint64_t>(tree_.nodeCount());
  for (const std::vector<Sum>* sums : {&complete_, &open_})
    for (const auto& [key, sum] : *sums) {
      const auto r = static_cast<int64_t>(key / nodeCount);
      visit(r, static_cast<int64_t>(key % nodeCount), sum / tree_.area(r));
    }
}

void LinkTally::clear() {
  open_ = {};
  complete_ = {};
}

Links LinkTally::links() const {
  const auto nodeCount = static_cast<uint64_t>(tree_.nodeCount());
  std::vector<Sum> sorted(complete_);
  sorted.insert(sorted.end(), open_.begin(), open_.end());
  sumAlike(sorted);
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

Vec3 kernelGradient(const NodeShape& receiver, const NodeShape& source) {
  const Vec3 v = source.centroid - receiver.centroid;
  const double d2 = dot(v, v), towards = dot(receiver.normal, v), back = -dot(source.normal, v);
  if (towards <= 0 || back <= 0 || d2 <= 0) return Vec3{};
  Vec3 g = (-1.0 / towards) * receiver.normal + (1.0 / back) * source.normal + (4.0 / d2) * v;
  g = g - dot(g, receiver.normal) * receiver.normal;  // along the receiver's plane
  // No patch of the receiver gets less than half the mean or more than 1.5 times it.
  const double reach = length(g) * receiver.radius;
  return reach > 0.5 ? (0.5 / reach) * g : g;
}

Vec3 childrenCentre(const PatchTree& tree, int64_t id) {
  const auto [a, b] = tree.children(id);
  const double areaA = tree.area(a), areaB = tree.area(b), area = areaA + areaB;
  if (area <= 0) return tree.node(id).centroid;
  return (areaA / area) * tree.node(a).centroid + (areaB / area) * tree.node(b).centroid;
}

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
      slope[r] = slope[r] +
                 light * kernelGradient(shapeOf(tree.node(r)), shapeOf(tree.node(links.source[k])));
  }
  // Push: a parent before its children; a linear node's light at each child's centroid (the
  // area-weighted mean of the children's values is the parent's: power is kept).
  for (int64_t id = 0; id < tree.innerCount(); ++id) {
    const Vec3 centre = push == Push::kLinear ? childrenCentre(tree, id) : Vec3{};
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
