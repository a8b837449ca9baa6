#include "jobs/safe_points.h"

#include <algorithm>

namespace radiosity::jobs {

namespace {

// Set by the handler, read at safe points: the only thing a signal handler may safely do.
volatile std::sig_atomic_t requestedSignal = 0;

void requestStop(int signal) { requestedSignal = signal; }

constexpr int kStopSignals[3] = {SIGTERM, SIGINT, SIGUSR1};

}  // namespace

SafePoints::SafePoints(MPI_Comm comm, bool enabled, double everySeconds)
    : comm_(comm), enabled_(enabled), everySeconds_(everySeconds), lastCheckpoint_(MPI_Wtime()) {
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
  // Rank 0's clock decides when a periodic checkpoint is due, so that all ranks agree.
  int local[2] = {
      static_cast<int>(requestedSignal),
      rank == 0 && everySeconds_ > 0 && MPI_Wtime() - lastCheckpoint_ >= everySeconds_ ? 1 : 0};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm_);
  if (global[0] != 0) {
    signal_ = global[0];
    return solve::SafePointAction::kStop;
  }
  return global[1] != 0 ? solve::SafePointAction::kSave : solve::SafePointAction::kContinue;
}

void SafePoints::checkpointWritten() { lastCheckpoint_ = MPI_Wtime(); }

std::string SafePoints::signalName() const {
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

}  // namespace radiosity::jobs
