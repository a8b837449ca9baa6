// Per-row values in and out of the PETSc vectors the channels share.
#include "solve/shared_system.h"

#include <algorithm>
#include <variant>

#include "solve/assemble.h"
#include "solve/single_precision_matrix.h"

namespace radiosity::solve {

PetscErrorCode setUpSharedSystem(FormFactorRows& rows, int64_t globalCount,
                                 const std::vector<double>& localArea,
                                 const std::vector<Rgb>& emission, bool symmetricForm,
                                 bool explicitMatrix, SharedSystem* s) {
  PetscFunctionBeginUser;
  auto* store = std::get_if<formfactor::SplitRows>(&rows);
  PetscCheck(
      !store || !store->pairsOnce || (store->singlePrecision && !symmetricForm && !explicitMatrix),
      PETSC_COMM_WORLD, PETSC_ERR_SUP,
      "rows stored once a pair serve only F's own single-precision operator");
  // (single-precision values cannot be an AIJ matrix's: a solver that changes M's entries in
  // place gets a double copy)
  if (store && !symmetricForm && !(store->singlePrecision && explicitMatrix)) {
    s->lent = std::move(*store);
    rows = formfactor::SparseRows();
    if (s->lent.singlePrecision) {
      PetscCall(createSinglePrecisionMatrix(PETSC_COMM_WORLD, s->lent, localArea, s->M.out()));
    } else {
      PetscCall(lendRows(PETSC_COMM_WORLD, s->lent, s->M.out()));
    }
  } else {
    PetscCall(std::visit(
        [&](const auto& r) {
          return assembleRows(PETSC_COMM_WORLD, r, symmetricForm ? &localArea : nullptr,
                              s->M.out());
        },
        rows));
  }
  PetscInt rowsInAll, columnsInAll;
  PetscCall(MatGetSize(s->M, &rowsInAll, &columnsInAll));
  PetscCheck(rowsInAll == globalCount, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
             "the ranks' rows add up to %" PetscInt_FMT " patches, not %" PetscInt_FMT, rowsInAll,
             static_cast<PetscInt>(globalCount));
  PetscCall(MatCreateVecs(s->M, s->B.out(), s->E.out()));
  for (OwnedVec* v : {&s->rho, &s->H, &s->weight, &s->area})
    PetscCall(VecDuplicate(s->E, v->out()));
  PetscCall(fillValues(s->area, localArea));
  if (symmetricForm) {
    PetscCall(VecCopy(s->area, s->weight));
  } else {
    PetscCall(VecSet(s->weight, 1.0));
  }
  std::vector<double> mask(emission.size());
  for (size_t r = 0; r < emission.size(); ++r) {
    const Rgb& e = emission[r];
    mask[r] = e[0] > 0 || e[1] > 0 || e[2] > 0 ? 1.0 : 0.0;
  }
  PetscCall(VecDuplicate(s->E, s->emitter.out()));
  PetscCall(fillValues(s->emitter, mask));
  PetscFunctionReturn(0);
}

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
