#include "io/store/collective_outputs.h"

#include "io/store/hdf5_parallel.h"
#include "io/core/error.h"

namespace radiosity {

using h5::broadcast;

CollectiveOutputs::CollectiveOutputs(MPI_Comm comm) : comm_(comm) { MPI_Comm_rank(comm, &rank_); }

std::string CollectiveOutputs::stage(const std::string& path, bool durable) {
  std::string temporary;
  if (rank_ == 0) temporary = batch_.stage(path, durable);
  broadcast(comm_, temporary);
  return temporary;
}

void CollectiveOutputs::commit() {
  // Every rank has closed its files before rank 0 renames them.
  MPI_Barrier(comm_);
  std::string error;
  if (rank_ == 0) {
    try {
      batch_.commit();
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  broadcast(comm_, error);
  if (!error.empty()) throw Error(exit_code::kFailure, error);
}

}  // namespace radiosity
