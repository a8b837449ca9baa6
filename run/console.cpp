#include "run/console.h"

#include "core/shown_text.h"
#include "parallel/collective.h"

namespace radiosity::run {

Console::Console(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &ranks_);
}

void Console::info(const std::string& line) const {
  if (rank_ != 0) return;
  if (log_) log_->write(line);
  if (!quiet_) std::fprintf(stderr, "%s\n", line.c_str());
}

void Console::result(const std::string& line) const {
  if (json_) return info(line);
  if (rank_ != 0) return;
  if (log_) log_->write(line);
  std::fprintf(stdout, "%s\n", line.c_str());
  std::fflush(stdout);
}

void Console::json(const std::string& document) const {
  if (rank_ != 0) return;
  std::fprintf(stdout, "%s\n", document.c_str());
  std::fflush(stdout);
}

void Console::warn(const std::string& line) const {
  if (rank_ != 0) return;
  const std::string shown = "radiosity: warning: " + shownMessage(line);
  if (log_) log_->write(shown);
  std::fprintf(stderr, "%s\n", shown.c_str());
}

double slowestRank(MPI_Comm comm, double seconds) {
  double slowest = seconds;
  MPI_Allreduce(&seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return slowest;
}

}  // namespace radiosity::run
