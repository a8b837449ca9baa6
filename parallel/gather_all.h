// Every patch's values on every rank, gathered from the ranks' blocks of rows: what the stages
// that need the whole scene's values (the discretisation estimate, a refinement round) share.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace radiosity {

/// Every patch's values on every rank from `local`, this rank's rows (rank blocks are in id
/// order, cut by count or by cost), counted in whole patches (T's bytes as they are: the ranks
/// of one job share a machine type), so that MPI's int counts reach 2^31 patches. Collective.
template <class T>
std::vector<T> gatherAll(MPI_Comm comm, const std::vector<T>& local, int64_t count) {
  static_assert(std::is_trivially_copyable_v<T>);
  int ranks;
  MPI_Comm_size(comm, &ranks);
  MPI_Datatype element;
  MPI_Type_contiguous(static_cast<int>(sizeof(T)), MPI_BYTE, &element);
  MPI_Type_commit(&element);
  std::vector<int> counts(ranks), offsets(ranks, 0);
  const int mine = static_cast<int>(local.size());
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<T> all(count);
  MPI_Allgatherv(local.data(), mine, element, all.data(), counts.data(), offsets.data(), element,
                 comm);
  MPI_Type_free(&element);
  return all;
}

}  // namespace radiosity
