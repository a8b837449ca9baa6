// Stopping a batch job without losing work: SIGTERM, SIGINT and SIGUSR1 (what schedulers send
// before the time limit) only set a flag; the run looks at it at safe points, where every rank
// decides the same thing together: go on, write a checkpoint (periodically) or write one and
// stop (exit code 75).
#pragma once

#include <mpi.h>

#include <csignal>
#include <string>

#include "solve/solve.h"

namespace radiosity::jobs {

class SafePoints {
 public:
  /// Without a checkpoint (`enabled` false) the signals keep their default action and poll()
  /// costs nothing. `everySeconds` ≤ 0: no periodic checkpoints.
  SafePoints(MPI_Comm comm, bool enabled, double everySeconds);
  ~SafePoints();
  SafePoints(const SafePoints&) = delete;
  SafePoints& operator=(const SafePoints&) = delete;

  /// Collective when enabled (one MPI_Allreduce): the decision of all ranks, the same on each.
  solve::SafePointAction poll();
  /// A checkpoint was written: the periodic clock starts again.
  void checkpointWritten();
  /// The name of the signal that asked to stop ("SIGTERM"), once poll() said kStop.
  std::string signalName() const;

 private:
  MPI_Comm comm_;
  bool enabled_;
  double everySeconds_, lastCheckpoint_;
  int signal_ = 0;
  struct sigaction previous_[3];
};

}  // namespace radiosity::jobs
