// Rank-aware output and collective failure handling for the program's commands.
#pragma once

#include <mpi.h>

#include <cstdio>
#include <functional>
#include <string>

namespace radiosity::jobs {

/// Prints on rank 0 only (deal.II's pcout), as a Unix tool does: what a command is run for (a
/// report, a description, help) to stdout, the log of how it went to stderr, warnings and errors
/// to stderr always.
class Console {
 public:
  explicit Console(MPI_Comm comm);
  bool isRoot() const { return rank_ == 0; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  MPI_Comm comm() const { return comm_; }
  /// A line of the log (stderr).
  void info(const std::string& line) const;
  /// A line of what the command is for (stdout, quiet or not).
  void result(const std::string& line) const;
  void warn(const std::string& line) const;

 private:
  MPI_Comm comm_;  ///< not owned
  int rank_ = 0, ranks_ = 1;
};

/// Wall time of a stage, the slowest rank's (collective).
double slowestRank(MPI_Comm comm, double seconds);

}  // namespace radiosity::jobs
