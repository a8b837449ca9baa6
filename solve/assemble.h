// Private to solve/: sparse rows of F into a preallocated PETSc MPIAIJ matrix, or F's one store
// lent to PETSc as its arrays and taken back.
#pragma once

#include <petscmat.h>

#include <limits>
#include <vector>

#include "formfactor/formfactor.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

/// diag(rowScale) F over the entries F_ij ≥ dropBelow (all by default; no scaling when
/// rowScale is null), with an explicit zero on the diagonal so that the matrix can be shifted
/// in place. F comes as values, or as a tally turned into values on the way in (no copy of F in
/// between). Collective on comm; the rank's rows are its rows of the matrix.
PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SparseRows& rows,
                            const std::vector<double>* rowScale, Mat* matrix,
                            double dropBelow = -std::numeric_limits<double>::infinity());
PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SampleTally& rows,
                            const std::vector<double>* rowScale, Mat* matrix,
                            double dropBelow = -std::numeric_limits<double>::infinity());

/// The same from F's one store, by copying its values in (for a row-scaled M, or where PETSc's
/// indices are not 32-bit).
PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SplitRows& rows,
                            const std::vector<double>* rowScale, Mat* matrix,
                            double dropBelow = -std::numeric_limits<double>::infinity());

/// M = F on the arrays of F's one store, without a copy (MatCreateMPIAIJWithSplitArrays): `rows`
/// must outlive M and stay where it is, and PETSc renumbers its off-diagonal columns meanwhile
/// (rows.columnMap says how). Where PETSc's indices are not 32-bit, the values are copied in
/// instead (assembleRows). Collective.
PetscErrorCode lendRows(MPI_Comm comm, formfactor::SplitRows& rows, Mat* matrix);

/// Destroys M made by lendRows and gives `rows` its global column ids back.
PetscErrorCode takeRowsBack(Mat* matrix, formfactor::SplitRows& rows);

}  // namespace radiosity::solve
