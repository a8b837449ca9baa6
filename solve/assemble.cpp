#include "solve/assemble.h"

namespace radiosity::solve {

PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SparseRows& rows,
                            const std::vector<double>* rowScale, Mat* S, double dropBelow) {
  const PetscInt local = static_cast<PetscInt>(rows.rowCount());
  const PetscInt first = static_cast<PetscInt>(rows.firstRow), end = first + local;
  std::vector<PetscInt> diagonalCount(local, 1), offDiagonalCount(local, 0);
  for (PetscInt r = 0; r < local; ++r) {
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      if (rows.value[k] < dropBelow || rows.column[k] == first + r) continue;
      const bool inBlock = rows.column[k] >= first && rows.column[k] < end;
      ++(inBlock ? diagonalCount[r] : offDiagonalCount[r]);
    }
  }
  PetscFunctionBeginUser;
  PetscCall(MatCreate(comm, S));
  PetscCall(MatSetSizes(*S, local, local, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(*S, MATMPIAIJ));
  PetscCall(MatMPIAIJSetPreallocation(*S, 0, diagonalCount.data(), 0, offDiagonalCount.data()));
  PetscCall(MatSetOption(*S, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  for (PetscInt r = 0; r < local; ++r) {
    const PetscInt row = first + r;
    columns.assign({row});
    values.assign({0.0});  // explicit zero diagonal: room for MatShift without reallocation
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      if (rows.value[k] < dropBelow) continue;
      columns.push_back(static_cast<PetscInt>(rows.column[k]));
      values.push_back(rowScale ? (*rowScale)[r] * rows.value[k] : rows.value[k]);
    }
    PetscCall(MatSetValues(*S, 1, &row, static_cast<PetscInt>(columns.size()), columns.data(),
                           values.data(), ADD_VALUES));
  }
  PetscCall(MatAssemblyBegin(*S, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*S, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
