#include <climits>
#include <exception>

#include "io/core/error.h"
#include "io/store/collective.h"

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
  // The lowest failing rank speaks for all, so the message is printed once and is the same.
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int mine = code != exit_code::kOk ? rank : INT_MAX, first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == INT_MAX) return;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&code, 1, MPI_INT, first, comm);
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  message.resize(length);
  MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
  throw Error(code, message);
}

}  // namespace radiosity
