// F as PETSc's operator when its one store holds single-precision values (8 B a nonzero instead
// of AIJ's 12): PETSc's matrices hold PetscScalar (double here), so a shell matrix multiplies by
// the store's float values itself, reading each in double.
#pragma once

#include <petscmat.h>

#include <vector>

#include "core/matrix_rows.h"

namespace radiosity::solve {

/// M = F on the arrays of `rows` (rows.singlePrecision, the rank's rows whole), without a copy:
/// a PETSc shell with the operations the solve asks of M (the product, the diagonal, each row's
/// largest entry, MatGetRow, MatGetInfo's nonzeros). Like PETSc's MPIAIJ it numbers the
/// off-diagonal block's columns compactly in place and leaves the map back to global ids in
/// rows.columnMap, which takeRowsBack undoes. `rows` must outlive the matrix. Collective.
/// Rows stored once a pair (rows.pairsOnce) are F with each stored F_ij's mirror F_ji =
/// F_ij A_i / A_j (`area`: the rows' areas) and F_ii the row's rest less its mirrors' sum: the
/// product adds the mirrors (Fᵀ of the stored entries, sent home by a reverse scatter), the row
/// maxima take theirs, MatGetRow refuses (a row's mirrors are other ranks').
PetscErrorCode createSinglePrecisionMatrix(MPI_Comm comm, SplitRows& rows,
                                           const std::vector<double>& area, Mat* M);

/// True for a matrix createSinglePrecisionMatrix made.
bool isSinglePrecisionMatrix(Mat M);

/// True for one made on rows stored once a pair (its rows cannot be read whole).
bool holdsPairsOnce(Mat M);

/// F ⊗ I_k on the same store as `M` (made by createSinglePrecisionMatrix): k channels
/// interleaved patch by patch, each row of F read once for all of them, as PETSc's MAIJ matrix
/// does for an AIJ one. Collective.
PetscErrorCode createSinglePrecisionComponents(Mat M, PetscInt k, Mat* block);

}  // namespace radiosity::solve
