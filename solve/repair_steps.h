// Private to solve/: the steps of repairFormFactors (reciprocity.cpp) on S = diag(A) F, an
// MPIAIJ matrix of this rank's rows: how far S is from symmetric and its symmetric part
// (repair_symmetry.cpp), and restoring its row sums (repair_closure.cpp).
#pragma once

#include <petscmat.h>

#include "solve/repair.h"

namespace radiosity::solve {

/// Global sums (or maxima) of a few doubles.
inline PetscErrorCode allReduce(MPI_Comm comm, double* values, int count, MPI_Op op) {
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, op, comm));
  PetscFunctionReturn(0);
}

/// The figures of measureDefect.
struct Defect {
  double relative = 0;  ///< ‖S − Sᵀ‖_F / ‖S‖_F
  double maxPair = 0;   ///< max |S_ij − S_ji| / max(S_ij, S_ji) over two-sided pairs
  double oneSided = 0;  ///< share of nonzeros whose transposed entry is zero
  double largest = 0;   ///< max S_ij
};

/// How far S (with St = Sᵀ) is from symmetric.
PetscErrorCode measureDefect(MPI_Comm comm, Mat S, Mat St, Defect* defect);

/// (S + St)/2 on the union of the patterns, built row by row from this rank's rows of both
/// (no communication: St = Sᵀ holds the mirrored entries). (i,j) and (j,i) get the same sum.
PetscErrorCode symmetricPart(MPI_Comm comm, Mat S, Mat St, Mat* out);

/// ‖S − S_raw‖_F / ‖S_raw‖_F (the patterns differ: dropped and mirrored entries).
PetscErrorCode relativeChange(MPI_Comm comm, Mat S, Mat raw, double* change);

/// max_i |Σ_j S_ij − target_i| / A_i: the closure error in units of F.
PetscErrorCode closureError(Mat S, Vec ones, Vec target, Vec area, double* error);

/// Restores every row sum of S to its target t_i: with `symmetric`, by Lawson's passes
/// S_ij (1 + λ_i + λ_j), which keep S symmetric, until the closure error (starting from
/// report->closureAfter) is below round-off; without, by scaling each row. Fills the report's
/// closureAfter, iterations, converged and emptyRows (global).
PetscErrorCode restoreRowSums(MPI_Comm comm, Mat S, Vec ones, Vec target, Vec area, bool symmetric,
                              RepairReport* report);

}  // namespace radiosity::solve
