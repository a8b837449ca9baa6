// Private to solve/: this rank's rows of a PETSc matrix, one at a time, each handed back to
// PETSc (MatRestoreRow) before the next is asked for.
#pragma once

#include <petscmat.h>

namespace radiosity::solve {

/// Calls visit(row, count, columns, values) for every row this rank owns of M, in order
/// (`row` global; `columns` ascending). `visit` only reads: it cannot fail.
template <class Visit>
PetscErrorCode forEachLocalRow(Mat M, Visit&& visit) {
  PetscInt first, end;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(M, &first, &end));
  for (PetscInt row = first; row < end; ++row) {
    PetscInt count;
    const PetscInt* columns;
    const PetscScalar* values;
    PetscCall(MatGetRow(M, row, &count, &columns, &values));
    visit(row, count, columns, values);
    PetscCall(MatRestoreRow(M, row, &count, &columns, &values));
  }
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
