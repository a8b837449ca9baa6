// A PETSc vector's local entries as a std::vector, for the tests that compare them.
#pragma once

#include <gtest/gtest.h>
#include <petscvec.h>

#include <vector>

namespace radiosity::testing {

inline std::vector<PetscScalar> entries(Vec v) {
  PetscInt n;
  const PetscScalar* a;
  EXPECT_EQ(VecGetLocalSize(v, &n), 0);
  EXPECT_EQ(VecGetArrayRead(v, &a), 0);
  std::vector<PetscScalar> out(a, a + n);
  EXPECT_EQ(VecRestoreArrayRead(v, &a), 0);
  return out;
}

}  // namespace radiosity::testing
