// MPI for GoogleTest programs whose main() is gtest_main's: started before the tests and ended
// after them by a global environment, plus the world's rank and size.
#pragma once

#include <gtest/gtest.h>
#include <mpi.h>

namespace radiosity::testing {

class MpiEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    int started = 0;
    MPI_Initialized(&started);
    if (!started) MPI_Init(nullptr, nullptr);
  }
  void TearDown() override {
    int ended = 0;
    MPI_Finalized(&ended);
    if (!ended) MPI_Finalize();
  }
};

inline ::testing::Environment* const kMpiEnvironment =
    ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

inline int worldRank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

inline int worldSize() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

}  // namespace radiosity::testing
