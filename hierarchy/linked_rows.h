// What a rank keeps of its sampled rows under hierarchical transport, a piece of rows at a
// time, instead of the flat F: the links of its rows (LinkTally) and, per row, the light that
// comes straight from the emitters, D_i = Σ_{j emits} F_ij E_j, kept apart because its shadows
// are sharp where the reflected light is smooth; the links carry only B − E. With them the
// radiosity is B = E + ρ ∘ (D + T (B − E)), T = push · links · pull (block_transport.h).
#pragma once

#include <vector>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "hierarchy/links.h"
#include "partition/partition.h"

namespace radiosity::hierarchy {

class LinkedRows {
 public:
  /// The rows `owned` of `patches` (the mesh `tree` was built over; both must outlive it).
  LinkedRows(const PatchTree& tree, const LinkOracle& oracle, const Mesh& patches,
             partition::PatchRange owned);
  /// Adds a piece of the owned rows (all with the same samples).
  void add(const SampleTally& piece);
  /// Per owned row: D_i.
  const std::vector<Rgb>& direct() const { return direct_; }
  /// The links of the rows added so far: as a sorted copy, or as they are kept.
  Links links() const { return tally_.links(); }
  const LinkTally& tally() const { return tally_; }
  int64_t linkCount() const { return tally_.size(); }
  /// Lets the links go, once the transport holds them.
  void dropLinks() { tally_.clear(); }

 private:
  LinkTally tally_;
  const Mesh& patches_;
  partition::PatchRange owned_;
  std::vector<Rgb> direct_;
};

}  // namespace radiosity::hierarchy
