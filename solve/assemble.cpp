#include "solve/assemble.h"

#include <type_traits>

namespace radiosity::solve {

namespace {

using formfactor::SplitRows;

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

PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SplitRows& rows,
                            const std::vector<double>* rowScale, Mat* S, double dropBelow) {
  return assembleRows(comm, formfactor::toFormFactors(rows), rowScale, S, dropBelow);
}

PetscErrorCode lendRows(MPI_Comm comm, formfactor::SplitRows& rows, Mat* M) {
  PetscFunctionBeginUser;
  if constexpr (!std::is_same_v<PetscInt, int32_t>) {
    PetscCall(assembleRows(comm, rows, nullptr, M));
  } else {
    const auto local = static_cast<PetscInt>(rows.rowCount());
    PetscCheck(rows.endRow - rows.firstRow == rows.rowCount() && !rows.columnMap, comm,
               PETSC_ERR_ARG_WRONG, "the store must hold its rows whole, with global columns");
    SplitRows::Block& own = rows.diagonalBlock;
    SplitRows::Block& other = rows.offDiagonalBlock;
    PetscCall(MatCreateMPIAIJWithSplitArrays(comm, local, local, PETSC_DETERMINE, PETSC_DETERMINE,
                                             own.rowStart.data(), own.column.data(),
                                             own.value.data(), other.rowStart.data(),
                                             other.column.data(), other.value.data(), M));
    // PETSc keeps the arrays and numbers the off-diagonal block's columns compactly in place;
    // its map back to global ids lets the store be read meanwhile (SplitRows::columnMap).
    Mat diagonal, offDiagonal;
    const PetscInt* columnMap;
    PetscCall(MatMPIAIJGetSeqAIJ(*M, &diagonal, &offDiagonal, &columnMap));
    PetscInt rowsOf, columnsOf, n;
    PetscCall(MatGetSize(offDiagonal, &rowsOf, &columnsOf));
    const PetscInt *start, *column;
    PetscBool done;
    PetscCall(MatGetRowIJ(offDiagonal, 0, PETSC_FALSE, PETSC_FALSE, &n, &start, &column, &done));
    PetscCheck(done && column == other.column.data(), comm, PETSC_ERR_PLIB,
               "PETSc copied the off-diagonal block instead of keeping F's store");
    PetscCall(
        MatRestoreRowIJ(offDiagonal, 0, PETSC_FALSE, PETSC_FALSE, &n, &start, &column, &done));
    PetscInt globalColumns;
    PetscCall(MatGetSize(*M, nullptr, &globalColumns));
    rows.columnMap = columnsOf < globalColumns ? columnMap : nullptr;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode takeRowsBack(Mat* M, formfactor::SplitRows& rows) {
  PetscFunctionBeginUser;
  if (rows.columnMap) {  // global ids back, before PETSc's map goes with M
    std::vector<int32_t>& column = rows.offDiagonalBlock.column;
    for (int32_t& j : column) j = rows.columnMap[j];
    rows.columnMap = nullptr;
  }
  PetscCall(MatDestroy(M));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
