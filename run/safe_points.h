// Stopping a batch job without losing work: SIGTERM, SIGINT and SIGUSR1 (what schedulers send
// before the time limit) only set a flag; the run looks at it at safe points, where every rank
// decides the same thing together: go on, write a checkpoint (periodically) or write one and
// stop (exit code 75). --stop-after stops it the same way on its own clock, before the job's
// time limit, so that no signal is needed (GROMACS's -maxh).
#pragma once

#include <mpi.h>

#include <csignal>
#include <string>

#include "solve/solve.h"

namespace radiosity::run {

class SafePoints {
 public:
  /// Without a checkpoint (`enabled` false) the signals keep their default action and poll()
  /// costs nothing. `everySeconds` ≤ 0: no periodic checkpoints. `stopAfterSeconds` > 0: stop
  /// at the last safe point from which the next one and a checkpoint write still end before
  /// `startedAt` (MPI_Wtime) + stopAfterSeconds.
  SafePoints(MPI_Comm comm, bool enabled, double everySeconds, double stopAfterSeconds = 0,
             double startedAt = MPI_Wtime());
  ~SafePoints();
  SafePoints(const SafePoints&) = delete;
  SafePoints& operator=(const SafePoints&) = delete;

  /// Collective when enabled (one MPI_Allreduce): the decision of all ranks, the same on each.
  solve::SafePointAction poll();
  /// Whether a stop was asked for (a signal, or the --stop-after deadline) since the handlers
  /// were installed, the same on every rank; starts the clock of the stretches poll() measures.
  /// For the first safe point after loading and meshing, which are not stretches between safe
  /// points. Collective when enabled.
  bool stopRequested();
  /// The checkpoint poll() asked for is written: the periodic clock starts again.
  void checkpointWritten();
  /// Why poll() said kStop: "SIGTERM", or "--stop-after 3h50m".
  std::string stopReason() const;

 private:
  bool deadlineNear(double now) const;

  MPI_Comm comm_;
  bool enabled_;
  double everySeconds_, lastCheckpoint_;
  double stopAfter_, startedAt_;
  // Rank 0's measures of what the run needs to stop: the longest stretch between two safe
  // points and the longest checkpoint write.
  double lastPoll_, longestStretch_ = 0, writeStarted_ = 0, longestWrite_ = 0;
  int signal_ = 0;
  bool deadline_ = false;
  struct sigaction previous_[3];
};

}  // namespace radiosity::run
