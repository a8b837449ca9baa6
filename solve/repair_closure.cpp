// Restoring the row sums of S = diag(A) F after dropping or symmetrising: Lawson's
// least-squares correction S'_ij = S_ij (1 + λ_i + λ_j) with λ from a CG solve when S must stay
// symmetric, else one multiplier per row.
#include <petscksp.h>

#include <cmath>

#include "solve/petsc_handles.h"
#include "solve/repair_steps.h"

namespace radiosity::solve {

namespace {

/// Closure at which the Lawson passes stop (row sums of F are at most 1).
constexpr double kClosureTolerance = 1e-13;
constexpr int kMaxLawsonPasses = 3;

PetscErrorCode createClosureSolver(MPI_Comm comm, Vec target, KSP* ksp) {
  PC pc;
  PetscReal targetNorm;
  PetscFunctionBeginUser;
  PetscCall(VecNorm(target, NORM_2, &targetNorm));
  PetscCall(KSPCreate(comm, ksp));
  PetscCall(KSPSetOptionsPrefix(*ksp, "repair_"));  // -repair_ksp_monitor etc.
  PetscCall(KSPSetType(*ksp, KSPCG));
  PetscCall(KSPGetPC(*ksp, &pc));
  // Point Jacobi: the same on any number of ranks (block preconditioners are not).
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(KSPSetNormType(*ksp, KSP_NORM_UNPRECONDITIONED));
  // The residual is the closure error itself (in units of S): stop near round-off of t.
  PetscCall(KSPSetTolerances(*ksp, 1e-14, 1e-15 * targetNorm, PETSC_DEFAULT, 10000));
  PetscCall(KSPSetFromOptions(*ksp));
  PetscFunctionReturn(0);
}

// One pass of Lawson's correction: (diag(S·1) + S) λ = t − S·1, then S ← S + ΛS + SΛ, i.e.
// S_ij (1 + λ_i + λ_j). Entries (i,j) and (j,i) get the same two products summed, so a
// symmetric S stays symmetric bit for bit. Rows without entries keep λ_i = 0.
PetscErrorCode lawsonPass(Mat S, Vec ones, Vec target, KSP ksp, RepairReport* report,
                          int64_t* emptyRows) {
  OwnedVec sums, rhs, diagonal, lambda;
  OwnedMat M;
  PetscFunctionBeginUser;
  for (OwnedVec* v : {&sums, &rhs, &diagonal, &lambda}) PetscCall(VecDuplicate(target, v->out()));
  PetscCall(MatMult(S, ones, sums));
  PetscCall(VecWAXPY(rhs, -1.0, sums, target));
  PetscCall(VecCopy(sums, diagonal));
  {
    PetscScalar *d, *b;
    const PetscScalar* t;
    PetscInt n;
    PetscCall(VecGetLocalSize(diagonal, &n));
    PetscCall(VecGetArray(diagonal, &d));
    PetscCall(VecGetArray(rhs, &b));
    PetscCall(VecGetArrayRead(target, &t));
    *emptyRows = 0;
    for (PetscInt r = 0; r < n; ++r) {
      if (d[r] > 0) continue;
      if (t[r] > 0) ++*emptyRows;  // nothing left to scale: this row cannot be closed
      d[r] = 1;
      b[r] = 0;
    }
    PetscCall(VecRestoreArrayRead(target, &t));
    PetscCall(VecRestoreArray(rhs, &b));
    PetscCall(VecRestoreArray(diagonal, &d));
  }
  PetscCall(MatDuplicate(S, MAT_COPY_VALUES, M.out()));
  PetscCall(MatDiagonalSet(M, diagonal, ADD_VALUES));
  PetscCall(KSPSetOperators(ksp, M, M));
  PetscCall(VecSet(lambda, 0.0));
  PetscCall(KSPSolve(ksp, rhs, lambda));

  KSPConvergedReason reason;
  PetscInt iterations;
  PetscReal lambdaNorm;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetIterationNumber(ksp, &iterations));
  PetscCall(VecNorm(lambda, NORM_INFINITY, &lambdaNorm));
  report->iterations += iterations;
  if (reason < 0) report->converged = false;
  // CG's iterates only get better, so an unfinished solve is still applied; a breakdown
  // (indefinite: a component whose visibility graph is bipartite, like two facing plates, has
  // no symmetric closure) is not.
  if ((reason > 0 || reason == KSP_DIVERGED_ITS) && std::isfinite(lambdaNorm)) {
    OwnedMat T, U;
    PetscCall(MatDuplicate(S, MAT_COPY_VALUES, T.out()));
    PetscCall(MatDuplicate(S, MAT_COPY_VALUES, U.out()));
    PetscCall(MatDiagonalScale(T, lambda, nullptr));  // ΛS
    PetscCall(MatDiagonalScale(U, nullptr, lambda));  // SΛ
    PetscCall(MatAXPY(T, 1.0, U, SAME_NONZERO_PATTERN));
    PetscCall(MatAXPY(S, 1.0, T, SAME_NONZERO_PATTERN));
  }
  PetscFunctionReturn(0);
}

// Without symmetry the least-squares closure is one multiplier per row: S_ij t_i / Σ_j S_ij.
PetscErrorCode scaleRows(Mat S, Vec ones, Vec target, int64_t* emptyRows) {
  OwnedVec scale;
  PetscScalar* s;
  const PetscScalar* t;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(target, scale.out()));
  PetscCall(MatMult(S, ones, scale));
  PetscCall(VecGetLocalSize(scale, &n));
  PetscCall(VecGetArray(scale, &s));
  PetscCall(VecGetArrayRead(target, &t));
  *emptyRows = 0;
  for (PetscInt r = 0; r < n; ++r) {
    if (s[r] > 0) {
      s[r] = t[r] / s[r];
    } else {
      if (t[r] > 0) ++*emptyRows;
      s[r] = 1;
    }
  }
  PetscCall(VecRestoreArrayRead(target, &t));
  PetscCall(VecRestoreArray(scale, &s));
  PetscCall(MatDiagonalScale(S, scale, nullptr));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode closureError(Mat S, Vec ones, Vec target, Vec area, double* error) {
  OwnedVec sums;
  PetscReal norm;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(target, sums.out()));
  PetscCall(MatMult(S, ones, sums));
  PetscCall(VecAXPY(sums, -1.0, target));
  PetscCall(VecPointwiseDivide(sums, sums, area));
  PetscCall(VecNorm(sums, NORM_INFINITY, &norm));
  *error = norm;
  PetscFunctionReturn(0);
}

PetscErrorCode restoreRowSums(MPI_Comm comm, Mat S, Vec ones, Vec target, Vec area, bool symmetric,
                              RepairReport* report) {
  PetscFunctionBeginUser;
  if (symmetric) {
    OwnedKsp ksp;
    PetscCall(createClosureSolver(comm, target, ksp.out()));
    for (int pass = 0; pass < kMaxLawsonPasses && report->closureAfter > kClosureTolerance;
         ++pass) {
      int64_t empty = 0;
      PetscCall(lawsonPass(S, ones, target, ksp, report, &empty));
      if (pass == 0) report->emptyRows = empty;
      PetscCall(closureError(S, ones, target, area, &report->closureAfter));
      if (!report->converged) break;
    }
  } else {
    PetscCall(scaleRows(S, ones, target, &report->emptyRows));
    PetscCall(closureError(S, ones, target, area, &report->closureAfter));
  }
  double empty = static_cast<double>(report->emptyRows);
  PetscCall(allReduce(comm, &empty, 1, MPI_SUM));
  report->emptyRows = static_cast<int64_t>(empty);
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
