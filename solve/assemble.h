// Private to solve/: sparse rows of F into a preallocated PETSc MPIAIJ matrix, and the exact
// sample tally back out of it.
#pragma once

#include <petscmat.h>

#include <limits>
#include <vector>

#include "formfactor/formfactor.h"
#include "solve/solve.h"

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

/// This rank's rows of M = F (assembled from a tally over `samples` samples per row whose
/// values give the sums back: formfactor::valuesKeepTheSums) as that tally again: the entries
/// that are not zero, their sums rebuilt exactly (formfactor::sumFromValue).
PetscErrorCode tallyFromMatrix(Mat M, int64_t samples, formfactor::SampleTally* tally);

}  // namespace radiosity::solve
