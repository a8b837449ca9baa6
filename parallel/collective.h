// Agreeing across ranks on the outcome of rank-local work, so that no rank is left waiting in a
// collective when another failed.
#pragma once

#include <mpi.h>

#include <functional>
#include <string>

namespace radiosity {

/// Runs `work` on every rank of `comm` and makes its outcome collective: if it threw on any
/// rank, every rank throws the Error of the lowest such rank (same exit code, same message).
/// Wrap rank-local work in it so that no rank is left waiting in a collective. Collective.
void runCollectively(MPI_Comm comm, const std::function<void()>& work);

/// The outcome of a step every rank took, the same on every rank: the lowest failing rank
/// speaks for all (so a message is printed once and is the same everywhere).
struct Agreement {
  int failingRank = -1;  ///< -1: no rank failed
  int exitCode = 0;
  std::string message;
  bool failed() const { return failingRank >= 0; }
};

/// Collects whether this rank `failed` (with its exit code and message) into one Agreement.
/// Collective.
Agreement agreeOnFailure(MPI_Comm comm, bool failed, int exitCode, const std::string& message);

}  // namespace radiosity
