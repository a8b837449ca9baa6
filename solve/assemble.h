// Private to solve/: sparse rows of F into a preallocated PETSc MPIAIJ matrix.
#pragma once

#include <petscmat.h>

#include <limits>
#include <vector>

#include "formfactor/formfactor.h"

namespace radiosity::solve {

/// diag(rowScale) F over the entries F_ij ≥ dropBelow (all by default; no scaling when
/// rowScale is null), with an explicit zero on the diagonal so that the matrix can be shifted
/// in place. Collective on comm; the rank's rows are its rows of the matrix.
PetscErrorCode assembleRows(MPI_Comm comm, const formfactor::SparseRows& rows,
                            const std::vector<double>* rowScale, Mat* matrix,
                            double dropBelow = -std::numeric_limits<double>::infinity());

}  // namespace radiosity::solve
