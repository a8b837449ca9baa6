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

}  // namespace radiosity
