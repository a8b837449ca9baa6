#include <climits>
#include <exception>

#include "core/error.h"
#include "parallel/collective.h"

namespace radiosity {

void runCollectively(MPI_Comm comm, const std::function<void()>& work) {
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
  const Agreement outcome = agreeOnFailure(comm, code != exit_code::kOk, code, message);
  if (outcome.failed()) throw Error(outcome.exitCode, outcome.message);
}

Agreement agreeOnFailure(MPI_Comm comm, bool failed, int exitCode, const std::string& message) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int mine = failed ? rank : INT_MAX, first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  Agreement outcome;
  if (first == INT_MAX) return outcome;
  outcome.failingRank = first;
  outcome.exitCode = exitCode;
  outcome.message = message;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&outcome.exitCode, 1, MPI_INT, first, comm);
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  outcome.message.resize(length);
  MPI_Bcast(outcome.message.data(), length, MPI_CHAR, first, comm);
  return outcome;
}

}  // namespace radiosity
