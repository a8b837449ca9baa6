// The hierarchical transport H = push(L · pull(B)) applied across ranks, each holding its block
// of patches (rows) and the links its own rows made (LinkTally over them). Every rank keeps the
// whole tree (a function of the mesh alone) and, per apply:
//  - pulls the means of the nodes inside its block from its own B, and those of the few nodes
//    that straddle two blocks from their children's means, which their owners share (one small
//    all-reduce): every mean is then the one the serial pull computes, bit for bit;
//  - fetches the means of the source nodes its links name inside other blocks (a PETSc star
//    forest, as a matrix's ghost columns are fetched);
//  - gathers each receiver's light over its links, the straddling receivers' partial sums added
//    up across ranks (a second small all-reduce), and pushes it down to its own patches.
// The answer is the serial transport's up to the order of those partial sums (round-off).
#pragma once

#include <mpi.h>
#include <petscsf.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "hierarchy/links.h"
#include "hierarchy/patch_tree.h"
#include "partition/partition.h"

namespace radiosity::hierarchy {

class BlockTransport {
 public:
  /// The transport over this rank's patches `owned` (each rank its own block; together every
  /// patch once, in rank order) by `links`, those of this rank's rows alone: a receiver holding
  /// patches of several blocks has a partial factor on each of their ranks. `tree` must outlive
  /// the object. Collective.
  static PetscErrorCode create(MPI_Comm comm, const PatchTree& tree, partition::PatchRange owned,
                               const Links& links, Push push,
                               std::unique_ptr<BlockTransport>* transport);
  /// The same from the tally's links as they are (no sorted copy of them is made).
  static PetscErrorCode create(MPI_Comm comm, const PatchTree& tree, partition::PatchRange owned,
                               const LinkTally& links, Push push,
                               std::unique_ptr<BlockTransport>* transport);
  ~BlockTransport();
  BlockTransport(const BlockTransport&) = delete;
  BlockTransport& operator=(const BlockTransport&) = delete;

  /// y = push(L · pull(x)) on the owned patches for `components` vectors at once, interleaved
  /// patch by patch (x and y each hold owned.size() · components values, and may not overlap):
  /// the links are read once for all of them. Collective.
  PetscErrorCode apply(const double* x, double* y, int components = 1);

  int64_t linkCount() const { return static_cast<int64_t>(factor_.size()); }
  /// Bytes the links and the per-node work arrays hold (not the tree).
  int64_t bytes() const;

 private:
  struct Local;  // the rank's view of the tree: which nodes it keeps and where
  BlockTransport(MPI_Comm comm, const PatchTree& tree, partition::PatchRange owned, Push push);
  /// `eachLink` visits every link once, a receiver's by source (twice: counted, then placed).
  static PetscErrorCode build(MPI_Comm comm, const PatchTree& tree, partition::PatchRange owned,
                              const std::function<void(const LinkVisitor&)>& eachLink, Push push,
                              std::unique_ptr<BlockTransport>* transport);
  PetscErrorCode placeLinks(const std::function<void(const LinkVisitor&)>& eachLink);
  PetscErrorCode connectGhosts(const std::vector<partition::PatchRange>& blocks);
  PetscErrorCode pull(const double* x, int components);
  void gather(int components);
  PetscErrorCode pushDown(double* y, int components);

  MPI_Comm comm_;
  const PatchTree& tree_;
  partition::PatchRange owned_;
  Push push_;
  std::unique_ptr<Local> local_;
  PetscSF ghosts_ = nullptr;  ///< roots: the rank's own nodes; leaves: the sources it fetches
  /// The links by receiver (local node index), each with its source's local index.
  std::vector<int64_t> receiverStart_;
  std::vector<int32_t> source_;  ///< (a rank keeps fewer than 2^31 nodes: PETSc's indices)
  std::vector<double> factor_;
  /// Per local node and component, as one apply goes: the pulled mean, the gathered light, its
  /// slope (linear push); and the straddling nodes' children's means and the partial sums shared.
  std::vector<double> mean_, gathered_;
  std::vector<Vec3> slope_;
  std::vector<double> shared_;
};

}  // namespace radiosity::hierarchy
