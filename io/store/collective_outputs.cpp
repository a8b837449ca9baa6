#include "io/store/collective_outputs.h"

#include "core/error.h"
#include "io/store/hdf5_parallel.h"
#include "parallel/collective.h"

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
  const Agreement outcome = agreeOnFailure(comm_, !error.empty(), exit_code::kFailure, error);
  if (outcome.failed()) throw Error(outcome.exitCode, outcome.message);
}

}  // namespace radiosity
