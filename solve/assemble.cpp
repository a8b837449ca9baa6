#include "solve/assemble.h"

#include "solve/local_rows.h"

namespace radiosity::solve {

namespace {

// The k-th value of either form of F: a stored value, or the tally's sum scaled on the fly.
struct ValuesOf {
  const std::vector<int64_t>& column;
  const std::vector<int64_t>& rowStart;
  const std::vector<double>* value = nullptr;
  const std::vector<int64_t>* sum = nullptr;
  double scale = 1;
  double operator[](int64_t k) const { return value ? (*value)[k] : (*sum)[k] * scale; }
};

PetscErrorCode assemble(MPI_Comm comm, int64_t firstRow, const ValuesOf& value,
                        const std::vector<double>* rowScale, Mat* S, double dropBelow) {
  const PetscInt local = static_cast<PetscInt>(value.rowStart.size()) - 1;
  const PetscInt first = static_cast<PetscInt>(firstRow), end = first + local;
  const std::vector<int64_t>& column = value.column;
  const std::vector<int64_t>& rowStart = value.rowStart;
  std::vector<PetscInt> diagonalCount(local, 1), offDiagonalCount(local, 0);
  for (PetscInt r = 0; r < local; ++r) {
    for (int64_t k = rowStart[r]; k < rowStart[r + 1]; ++k) {
      if (value[k] < dropBelow || column[k] == first + r) continue;
      const bool inBlock = column[k] >= first && column[k] < end;
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
    for (int64_t k = rowStart[r]; k < rowStart[r + 1]; ++k) {
      const double v = value[k];
      if (v < dropBelow) continue;
      columns.push_back(static_cast<PetscInt>(column[k]));
      values.push_back(rowScale ? (*rowScale)[r] * v : v);
    }
    PetscCall(MatSetValues(*S, 1, &row, static_cast<PetscInt>(columns.size()), columns.data(),
                           values.data(), ADD_VALUES));
  }
  PetscCall(MatAssemblyBegin(*S, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*S, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SparseRows& rows,
                            const std::vector<double>* rowScale, Mat* S, double dropBelow) {
  return assemble(comm, rows.firstRow, {rows.column, rows.rowStart, &rows.value, nullptr, 1},
                  rowScale, S, dropBelow);
}

PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SampleTally& rows,
                            const std::vector<double>* rowScale, Mat* S, double dropBelow) {
  // The same doubles as formfactor::toFormFactors gives.
  const double scale = 0x1p-32 / static_cast<double>(rows.samples);
  return assemble(comm, rows.firstRow, {rows.column, rows.rowStart, nullptr, &rows.sum, scale},
                  rowScale, S, dropBelow);
}

PetscErrorCode tallyFromMatrix(Mat M, int64_t samples, formfactor::SampleTally* tally) {
  PetscInt first, end;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(M, &first, &end));
  *tally = formfactor::SampleTally();
  tally->firstRow = first;
  tally->samples = samples;
  tally->rowStart.reserve(static_cast<size_t>(end - first) + 1);
  // One pass to size the arrays, so that the rebuilt tally takes what it needs and no more.
  int64_t entries = 0;
  PetscCall(
      forEachLocalRow(M, [&](PetscInt, PetscInt count, const PetscInt*, const PetscScalar* values) {
        for (PetscInt k = 0; k < count; ++k) entries += values[k] != 0 ? 1 : 0;
      }));
  tally->column.reserve(static_cast<size_t>(entries));
  tally->sum.reserve(static_cast<size_t>(entries));
  PetscCall(forEachLocalRow(
      M, [&](PetscInt, PetscInt count, const PetscInt* columns, const PetscScalar* values) {
        for (PetscInt k = 0; k < count; ++k) {
          if (values[k] == 0) continue;  // the explicit zero diagonal
          tally->column.push_back(columns[k]);
          tally->sum.push_back(formfactor::sumFromValue(values[k], samples));
        }
        tally->rowStart.push_back(static_cast<int64_t>(tally->column.size()));
      }));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
