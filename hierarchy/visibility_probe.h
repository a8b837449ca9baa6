// Whether a receiver cluster sees a source node whole, asked by the link oracle
// (LinkOracle::seesWhole) before it groups the receiver: a few probe rays between points of the
// two nodes' patches, blocked if any meets a patch outside them. Partial visibility inside a
// receiver (a table's shadow on a wall) is what makes the light it gathers vary sharply, so such
// receivers are split down to patches instead.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh.h"
#include "hierarchy/patch_tree.h"
#include "trace/trace.h"

namespace radiosity::hierarchy {

/// Probe rays between node pairs over `patches` (traced as `tracer`; both must outlive it). Each
/// ray's patches and points come from the named stream trace::kHierarchyProbe at a key of the
/// pair's ranges, so the answer is the same on any rank and thread count. Answers are remembered
/// in a table of bounded size, emptied when half full: a pair asked again after that is probed
/// again, to the same answer. Not thread-safe: one per thread.
class VisibilityProbe {
 public:
  VisibilityProbe(const trace::SceneTracer& tracer, const Mesh& patches, int rays = 8)
      : tracer_(tracer), patches_(patches), rays_(rays) {}

  /// Whether every probe ray from `receiver` to `source` is unblocked.
  bool seesWhole(const ClusterNode& receiver, const ClusterNode& source);
  /// The pairs probed so far (a pair asked again once forgotten counts again).
  int64_t probed() const { return probed_; }
  /// A LinkOracle::seesWhole that asks this probe (which must outlive it).
  auto asOracle() {
    return [this](const ClusterNode& r, const ClusterNode& s) { return seesWhole(r, s); };
  }

 private:
  Vec3 pointOn(const ClusterNode& node, uint64_t key, int k) const;
  bool probe(const ClusterNode& receiver, const ClusterNode& source, uint64_t key) const;

  const trace::SceneTracer& tracer_;
  const Mesh& patches_;
  int rays_;
  /// Open addressing: key (never 0) and answer per slot; 0 marks an empty slot.
  static constexpr size_t kSlots = size_t{1} << 19;
  std::vector<uint64_t> key_ = std::vector<uint64_t>(kSlots, 0);
  std::vector<uint8_t> clear_ = std::vector<uint8_t>(kSlots, 0);
  size_t used_ = 0;
  int64_t probed_ = 0;
};

}  // namespace radiosity::hierarchy
