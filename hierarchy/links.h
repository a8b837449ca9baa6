// Links: the light one node of the patch tree gathers from another, each the area-weighted mean
// form factor F_RS = (1/A_R) Σ_{i∈R} A_i Σ_{j∈S} F_ij, made from the same keyed rays as the flat
// F's rows, each ray's hit counted in the link the oracle chooses for its (patch, patch) pair.
// The transport over the leaves is then H = push(links · pull(B)): pull takes each source node's
// area-mean B, push hands each receiver node's gathered light to every patch under it.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/matrix_rows.h"
#include "hierarchy/patch_tree.h"

namespace radiosity::hierarchy {

/// When a pair of nodes may exchange light as one link: both subtend little of each other's
/// view ((r_R + r_S) / distance below `spread`) and each is near flat (its normals within
/// `cone` of their mean), so that F varies little over the receiver and the source's mean B is
/// what its hits see.
struct LinkOracle {
  double spread = 0.2;
  double cone = 0.35;  ///< radians (20°)
  /// Receivers are patches, never clusters: only the source side is grouped (no push).
  bool patchReceivers = false;
  /// Light straight from emitters reaches patches, not clusters: its shadows are sharp.
  bool patchReceiversOfEmitters = false;
  /// A receiver cluster lies within one input face (after contact cutting, a face does not
  /// run under a wall into the next room).
  bool receiversWithinFace = false;
  /// Whether a receiver cluster sees the whole source unobstructed (e.g. by probe rays between
  /// their patches); asked last, only of pairs the rest admits. Empty: not asked.
  std::function<bool(const ClusterNode& receiver, const ClusterNode& source)> seesWhole{};
};

bool admissible(const ClusterNode& receiver, const ClusterNode& source, const LinkOracle& oracle);

/// The link that carries patch `j`'s light to patch `i`: from (root, root) down, the larger of
/// the pair (by radius) split towards i or j until the pair is admissible or both are patches.
/// The links so chosen tile every (i, j) pair exactly once.
std::pair<int64_t, int64_t> linkOf(const PatchTree& tree, const LinkOracle& oracle, int64_t i,
                                   int64_t j);

/// What visits links one by one: (receiver, source, factor).
using LinkVisitor = std::function<void(int64_t receiver, int64_t source, double factor)>;

/// Links sorted by receiver, then source.
struct Links {
  std::vector<int64_t> receiver, source;
  std::vector<double> factor;
  int64_t size() const { return static_cast<int64_t>(factor.size()); }
  /// Visits each link once, in order.
  void forEach(const LinkVisitor& visit) const {
    for (int64_t k = 0; k < size(); ++k) visit(receiver[k], source[k], factor[k]);
  }
};

/// Links summed from rows as they are sampled, a piece of rows at a time, so that no flat F is
/// kept: each row's hits are counted in their links and the piece can go. A receiver node's
/// links are complete once every row of its patches has been added. Pieces may come in any
/// order; in increasing row order (as a rank samples its block) the links of receivers whose rows
/// are all in are set aside summed, and only the others' are sorted again with each piece.
class LinkTally {
 public:
  LinkTally(const PatchTree& tree, const LinkOracle& oracle) : tree_(tree), oracle_(oracle) {}
  /// Adds the rows `piece` holds (rows piece.firstRow on, over the mesh the tree was built
  /// from, all with the same samples).
  void add(const SampleTally& piece);
  /// The links so far, F_RS = Σ_{i∈R} A_i Σ_{j∈S} F_ij / A_R.
  Links links() const;
  /// Visits each link so far once, without a copy of them: a receiver's links one after
  /// another, by source (the receivers in no order).
  void forEach(const LinkVisitor& visit) const;
  /// Distinct links so far.
  int64_t size() const { return static_cast<int64_t>(complete_.size() + open_.size()); }
  /// Lets the links go (their memory too).
  void clear();

 private:
  /// Σ A_i F_iS of one link, the key receiver · nodes + source.
  struct Sum {
    uint64_t key;
    double sum;
  };
  const PatchTree& tree_;
  LinkOracle oracle_;
  /// The links of receivers with rows still to come (summed, in key order after each piece),
  /// and of those whose rows are all in (a receiver's together, by source); no link is in both.
  std::vector<Sum> open_, complete_;
  static void sumAlike(std::vector<Sum>& sums);
  int64_t rowsEnd_ = 0;  ///< the end of the last piece; −1 once a piece came out of order
};

/// The links of the rows `tally` holds (a LinkTally given them all at once).
Links linksFromRows(const PatchTree& tree, const LinkOracle& oracle, const SampleTally& tally);

/// Pull: each node's area-mean of `value` (per patch).
std::vector<double> pullMeans(const PatchTree& tree, const std::vector<double>& value);

/// How push hands a node's gathered light to its patches.
enum class Push {
  kUniform,  ///< the node's mean irradiance to every patch
  /// each link's light varied over the receiver as the point kernel cosθ cosθ' / d² varies
  /// (its gradient at the node's centroid): first-order in the node's size, and power kept
  kLinear,
};

/// What the point kernel between two nodes reads of each.
struct NodeShape {
  Vec3 centroid{}, normal{};
  double radius = 0;
};
inline NodeShape shapeOf(const ClusterNode& node) {
  return {node.centroid, node.normal, node.radius};
}

/// ∇ log(cosθ_R cosθ_S / d²) as the receiving point moves from the receiver's centroid along its
/// plane: how the point kernel from `source` varies over `receiver` (0 where either faces away at
/// the centroids), capped so that no point of the receiver gets less than half the mean or more
/// than 1.5 times it. What linear push varies a link's light by.
Vec3 kernelGradient(const NodeShape& receiver, const NodeShape& source);

/// The area-weighted mean of inner node `id`'s children's centroids, in doubles: the point linear
/// push varies a node's light about, so that its children's shares weigh to the node's exactly
/// (the node's own centroid is kept in floats).
Vec3 childrenCentre(const PatchTree& tree, int64_t id);

/// The irradiance the links carry to each patch from `radiosity` (per patch, one channel):
/// push(links · pull(radiosity)).
std::vector<double> transport(const PatchTree& tree, const Links& links,
                              const std::vector<double>& radiosity, Push push = Push::kUniform);

}  // namespace radiosity::hierarchy
