#include "jobs/console.h"

#include <climits>
#include <exception>

#include "io/io.h"

namespace radiosity::jobs {

Console::Console(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &ranks_);
}

void Console::info(const std::string& line) const {
  if (rank_ != 0) return;
  std::fprintf(stdout, "%s\n", line.c_str());
  std::fflush(stdout);
}

void Console::warn(const std::string& line) const {
  if (rank_ != 0) return;
  std::fprintf(stderr, "radiosity: warning: %s\n", line.c_str());
}

void runOnAllRanks(const Console& console, const std::function<void()>& work) {
  int code = exit_code::kOk;
  std::string message;
  try {
    work();
  } catch (const Error& e) {
    code = e.exitCode();
    message = e.what();
  } catch (const std::exception& e) {
    code = exit_code::kFailure;
    message = e.what();
  }
  // The lowest failing rank speaks for all, so the message is printed once.
  int failingRank = code != exit_code::kOk ? console.rank() : INT_MAX;
  int firstFailing = INT_MAX;
  MPI_Allreduce(&failingRank, &firstFailing, 1, MPI_INT, MPI_MIN, console.comm());
  if (firstFailing == INT_MAX) return;
  MPI_Bcast(&code, 1, MPI_INT, firstFailing, console.comm());
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, firstFailing, console.comm());
  message.resize(length);
  MPI_Bcast(message.data(), length, MPI_CHAR, firstFailing, console.comm());
  throw Error(code, message);
}

double slowestRank(MPI_Comm comm, double seconds) {
  double slowest = seconds;
  MPI_Allreduce(&seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return slowest;
}

}  // namespace radiosity::jobs
