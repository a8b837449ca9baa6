// Per-row values in and out of the PETSc vectors the channels share.
#include "solve/shared_system.h"

#include <algorithm>

namespace radiosity::solve {

PetscErrorCode fillChannel(Vec v, const std::vector<Rgb>& values, int c) {
  PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &array));
  for (size_t r = 0; r < values.size(); ++r) array[r] = values[r][c];
  PetscCall(VecRestoreArray(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode fillValues(Vec v, const std::vector<double>& values) {
  PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &array));
  std::copy(values.begin(), values.end(), array);
  PetscCall(VecRestoreArray(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode readChannel(Vec v, std::vector<Rgb>& values, int c) {
  const PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(v, &array));
  for (size_t r = 0; r < values.size(); ++r) values[r][c] = array[r];
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode multiplyF(Mat M, Vec weight, Vec x, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(MatMult(M, x, y));
  PetscCall(VecPointwiseDivide(y, y, weight));
  PetscFunctionReturn(0);
}

PetscErrorCode readChannelResults(const SharedSystem& s, int c, LocalSolution& solution) {
  PetscFunctionBeginUser;
  PetscCall(readChannel(s.B, solution.radiosity, c));
  PetscCall(multiplyF(s.M, s.weight, s.B, s.H));
  PetscCall(readChannel(s.H, solution.irradiance, c));
  PetscFunctionReturn(0);
}

void copyChannel(std::vector<Rgb>& values, int from, int to) {
  for (Rgb& v : values) v[to] = v[from];
}

}  // namespace radiosity::solve
