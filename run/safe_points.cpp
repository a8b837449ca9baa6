#include "run/safe_points.h"

#include <algorithm>

#include "run/duration.h"

namespace radiosity::run {

namespace {

// Set by the handler, read at safe points: the only thing a signal handler may safely do.
volatile std::sig_atomic_t requestedSignal = 0;

void requestStop(int signal) { requestedSignal = signal; }

constexpr int kStopSignals[3] = {SIGTERM, SIGINT, SIGUSR1};

}  // namespace

SafePoints::SafePoints(MPI_Comm comm, bool enabled, double everySeconds, double stopAfterSeconds,
                       double startedAt)
    : comm_(comm),
      enabled_(enabled),
      everySeconds_(everySeconds),
      lastCheckpoint_(MPI_Wtime()),
      stopAfter_(stopAfterSeconds),
      startedAt_(startedAt),
      lastPoll_(lastCheckpoint_) {
  if (!enabled_) return;
  requestedSignal = 0;
  struct sigaction action {};
  action.sa_handler = requestStop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // system calls (file I/O, MPI's) go on after the handler
  for (int k = 0; k < 3; ++k) sigaction(kStopSignals[k], &action, &previous_[k]);
}

SafePoints::~SafePoints() {
  if (!enabled_) return;
  for (int k = 0; k < 3; ++k) sigaction(kStopSignals[k], &previous_[k], nullptr);
}

solve::SafePointAction SafePoints::poll() {
  if (!enabled_) return solve::SafePointAction::kContinue;
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  // Rank 0's clock decides when a periodic checkpoint is due and when the deadline is near, so
  // that all ranks agree.
  const double now = MPI_Wtime();
  longestStretch_ = std::max(longestStretch_, now - lastPoll_);
  lastPoll_ = now;
  int local[3] = {static_cast<int>(requestedSignal),
                  rank == 0 && everySeconds_ > 0 && now - lastCheckpoint_ >= everySeconds_,
                  rank == 0 && deadlineNear(now)};
  int global[3] = {0, 0, 0};
  MPI_Allreduce(local, global, 3, MPI_INT, MPI_MAX, comm_);
  writeStarted_ = now;
  if (global[0] != 0 || global[2] != 0) {
    signal_ = global[0];
    deadline_ = global[0] == 0;
    return solve::SafePointAction::kStop;
  }
  return global[1] != 0 ? solve::SafePointAction::kSave : solve::SafePointAction::kContinue;
}

bool SafePoints::stopRequested() {
  if (!enabled_) return false;
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  const double now = MPI_Wtime();
  int local[2] = {static_cast<int>(requestedSignal), rank == 0 && deadlineNear(now)};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm_);
  lastPoll_ = writeStarted_ = now;
  if (global[0] == 0 && global[1] == 0) return false;
  signal_ = global[0];
  deadline_ = global[0] == 0;
  return true;
}

// Another stretch like the longest so far, then a checkpoint like the longest so far, would end
// past the deadline: stop now.
bool SafePoints::deadlineNear(double now) const {
  return stopAfter_ > 0 && now - startedAt_ + longestStretch_ + longestWrite_ >= stopAfter_;
}

void SafePoints::checkpointWritten() {
  lastCheckpoint_ = MPI_Wtime();
  longestWrite_ = std::max(longestWrite_, lastCheckpoint_ - writeStarted_);
  // The write is not a stretch of work between safe points.
  lastPoll_ = lastCheckpoint_;
}

std::string SafePoints::stopReason() const {
  if (deadline_) return "--stop-after " + describeDuration(stopAfter_);
  switch (signal_) {
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGUSR1:
      return "SIGUSR1";
    default:
      return "signal " + std::to_string(signal_);
  }
}

}  // namespace radiosity::run
