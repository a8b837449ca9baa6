// Private to io/store: the disk space of a file that parallel HDF5 is to write, taken before it
// writes. HDF5's collective calls (H5Dcreate2, H5Fflush, H5Fclose, ...) communicate inside; a
// write that fails on one rank only (a full disk, a quota) makes that rank leave the call early
// while the others wait in it for ever, which no agreement afterwards can mend. With the blocks
// allocated up front a full disk or a quota shows as one failed step, before any collective
// write, and every rank stops together.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/store/hdf5_parallel.h"

namespace radiosity::h5 {

/// An upper bound of the bytes a file written by io/store takes: its datasets (chunks rounded
/// up to whole chunks), its text and generous room for HDF5's own structures.
class SpaceEstimate {
 public:
  /// A dataset of `total` rows of `columns` values (0: 1-D) of `elementSize` bytes each.
  void dataset(int64_t total, int columns, size_t elementSize, Layout layout = Layout::kContiguous);
  /// An attribute or name of `length` bytes, stored `copies` times.
  void text(size_t length, int copies = 1);
  int64_t bytes() const;

 private:
  void add(double bytes);
  int64_t bytes_ = int64_t{256} << 10;  ///< the superblock, groups, heaps, aggregator slack
};

/// Creates `name` (empty or not there yet: a fresh temporary) and allocates `bytes` of disk to
/// it without changing its size (fallocate, FALLOC_FL_KEEP_SIZE), so that HDF5 opened on it with
/// H5F_ACC_TRUNC writes into space it already holds. Where the file system cannot allocate
/// ahead, the file is created and nothing is reserved. Rank-local; throws Failure naming the
/// size and the system's reason (ENOSPC, EDQUOT, ...).
void reserveSpace(const std::string& name, int64_t bytes);

/// Points this process's descriptors of `name` at an in-memory file, so that whatever HDF5
/// still writes to it (the metadata its closing flushes) succeeds and is thrown away. For a file
/// whose write failed: the flush is collective inside, and a write that fails on one rank only
/// would leave the others waiting in it; written nowhere, it fails nowhere. Rank-local; call it
/// on every rank, once they agreed the file is lost. Best effort: a descriptor it cannot move
/// stays as it was.
void discardFurtherWrites(const std::string& name) noexcept;

/// Gives back what the file did not use: truncating to its own size frees the blocks beyond
/// it. Rank-local; a failure leaves only unused blocks behind, so it is ignored.
void releaseUnusedSpace(const std::string& name) noexcept;

}  // namespace radiosity::h5
