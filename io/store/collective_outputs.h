// The outputs of one command run on a communicator (result, checkpoint): every rank writes its
// part of each file under the temporary name rank 0 chose, and rank 0 renames them all together
// once every rank has closed every file.
#pragma once

#include <mpi.h>

#include <string>

#include "core/atomic_file.h"

namespace radiosity {

class CollectiveOutputs {
 public:
  explicit CollectiveOutputs(MPI_Comm comm);

  MPI_Comm comm() const { return comm_; }

  /// The temporary name under which every rank writes `path` (OutputBatch::stage on rank 0,
  /// shared). Collective.
  std::string stage(const std::string& path, bool durable = false);

  /// Once every rank has closed its files: rank 0 renames them all into place. Throws
  /// Error(exit_code::kFailure) on every rank if that fails. Collective.
  void commit();

  /// Removes the temporary of `path` (its write failed); the others stay staged. Only rank 0
  /// acts, so any rank may call it.
  void unstage(const std::string& path) { batch_.unstage(path); }

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  OutputBatch batch_;  ///< used on rank 0 only
};

}  // namespace radiosity
