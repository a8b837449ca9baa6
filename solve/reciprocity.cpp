// Reciprocity and sparsification of estimated form factors, through PETSc. S = diag(A) F is an
// MPIAIJ matrix (explicit zero diagonal, so that diag(S·1) + S is formed in place); dropping
// happens while assembling, symmetrising is MatTranspose and a row-by-row merge of S and Sᵀ
// into the union pattern (no further communication), and the closure repair is
// Lawson's least-squares correction S'_ij = S_ij (1 + λ_i + λ_j) with λ from a CG solve. The
// PETSc-style functions return PetscErrorCode; repairFormFactors() turns failures into
// exceptions.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "solve/assemble.h"
#include "solve/solve.h"

namespace radiosity::solve {

namespace {

/// A repaired entry below −kClip · max S is kept (and counted); one above is round-off: 0.
constexpr double kClip = 1e-12;
/// Closure at which the Lawson passes stop (row sums of F are at most 1).
constexpr double kClosureTolerance = 1e-13;
constexpr int kMaxLawsonPasses = 3;

void check(PetscErrorCode code, const char* what) {
  if (code) {
    throw Error(exit_code::kFailure,
                std::string("PETSc failed in ") + what + " (error " + std::to_string(code) + ")");
  }
}

// Global sums (or maxima) of a few doubles.
PetscErrorCode allReduce(MPI_Comm comm, double* values, int count, MPI_Op op) {
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, op, comm));
  PetscFunctionReturn(0);
}

// Calls visit(row, column, x_ij, y_ij) for every (row, column) stored in X or in Y (the other
// one 0), over this rank's rows, columns ascending. X and Y have the same layout.
template <class Visit>
PetscErrorCode walkRows(Mat X, Mat Y, Visit&& visit) {
  PetscInt first, end;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(X, &first, &end));
  for (PetscInt row = first; row < end; ++row) {
    PetscInt nx, ny;
    const PetscInt *cx, *cy;
    const PetscScalar *vx, *vy;
    PetscCall(MatGetRow(X, row, &nx, &cx, &vx));
    PetscCall(MatGetRow(Y, row, &ny, &cy, &vy));
    for (PetscInt kx = 0, ky = 0; kx < nx || ky < ny;) {
      if (ky == ny || (kx < nx && cx[kx] < cy[ky])) {
        visit(row, cx[kx], vx[kx], 0.0);
        ++kx;
      } else if (kx == nx || cy[ky] < cx[kx]) {
        visit(row, cy[ky], 0.0, vy[ky]);
        ++ky;
      } else {
        visit(row, cx[kx], vx[kx], vy[ky]);
        ++kx;
        ++ky;
      }
    }
    PetscCall(MatRestoreRow(Y, row, &ny, &cy, &vy));
    PetscCall(MatRestoreRow(X, row, &nx, &cx, &vx));
  }
  PetscFunctionReturn(0);
}

struct Defect {
  double relative = 0;  ///< ‖S − Sᵀ‖_F / ‖S‖_F
  double maxPair = 0;   ///< max |S_ij − S_ji| / max(S_ij, S_ji) over two-sided pairs
  double oneSided = 0;  ///< share of nonzeros whose transposed entry is zero
  double largest = 0;   ///< max S_ij
};

// How far S (with St = Sᵀ) is from symmetric.
PetscErrorCode measureDefect(MPI_Comm comm, Mat S, Mat St, Defect* defect) {
  double sums[4] = {0, 0, 0, 0};  // Σ (S_ij − S_ji)², Σ S_ij², one-sided nonzeros, nonzeros
  double maxima[2] = {0, 0};      // max pair defect, max S_ij
  PetscFunctionBeginUser;
  PetscCall(walkRows(S, St, [&](PetscInt, PetscInt, double a, double b) {
    sums[0] += (a - b) * (a - b);
    sums[1] += a * a;
    maxima[1] = std::max(maxima[1], a);
    if (a == 0) return;
    sums[3] += 1;
    if (b == 0) {
      sums[2] += 1;
    } else {
      maxima[0] = std::max(maxima[0], std::abs(a - b) / std::max(a, b));
    }
  }));
  PetscCall(allReduce(comm, sums, 4, MPI_SUM));
  PetscCall(allReduce(comm, maxima, 2, MPI_MAX));
  defect->relative = sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) : 0;
  defect->oneSided = sums[3] > 0 ? sums[2] / sums[3] : 0;
  defect->maxPair = maxima[0];
  defect->largest = maxima[1];
  PetscFunctionReturn(0);
}

// (S + St)/2 on the union of the patterns, built row by row from this rank's rows of both
// (no communication: St = Sᵀ holds the mirrored entries). (i,j) and (j,i) get the same sum.
PetscErrorCode symmetricPart(MPI_Comm comm, Mat S, Mat St, Mat* out) {
  PetscInt first, end;
  std::vector<PetscInt> rowStart{0}, columns;
  std::vector<PetscScalar> values;
  PetscInt lastRow;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(S, &first, &end));
  lastRow = first;
  PetscCall(walkRows(S, St, [&](PetscInt row, PetscInt column, double a, double b) {
    for (; lastRow < row; ++lastRow) rowStart.push_back(static_cast<PetscInt>(columns.size()));
    columns.push_back(column);
    values.push_back((a + b) * 0.5);
  }));
  for (; lastRow < end; ++lastRow) rowStart.push_back(static_cast<PetscInt>(columns.size()));
  PetscCall(MatCreateMPIAIJWithArrays(comm, end - first, end - first, PETSC_DETERMINE,
                                      PETSC_DETERMINE, rowStart.data(), columns.data(),
                                      values.data(), out));
  PetscFunctionReturn(0);
}

// max_i |Σ_j S_ij − target_i| / A_i: the closure error in units of F.
PetscErrorCode closureError(Mat S, Vec ones, Vec target, Vec area, double* error) {
  Vec sums;
  PetscReal norm;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(target, &sums));
  PetscCall(MatMult(S, ones, sums));
  PetscCall(VecAXPY(sums, -1.0, target));
  PetscCall(VecPointwiseDivide(sums, sums, area));
  PetscCall(VecNorm(sums, NORM_INFINITY, &norm));
  *error = norm;
  PetscCall(VecDestroy(&sums));
  PetscFunctionReturn(0);
}

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
  Vec sums, rhs, diagonal, lambda;
  Mat M, T, U;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(target, &sums));
  PetscCall(VecDuplicate(target, &rhs));
  PetscCall(VecDuplicate(target, &diagonal));
  PetscCall(VecDuplicate(target, &lambda));
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
  PetscCall(MatDuplicate(S, MAT_COPY_VALUES, &M));
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
    PetscCall(MatDuplicate(S, MAT_COPY_VALUES, &T));
    PetscCall(MatDuplicate(S, MAT_COPY_VALUES, &U));
    PetscCall(MatDiagonalScale(T, lambda, nullptr));  // ΛS
    PetscCall(MatDiagonalScale(U, nullptr, lambda));  // SΛ
    PetscCall(MatAXPY(T, 1.0, U, SAME_NONZERO_PATTERN));
    PetscCall(MatAXPY(S, 1.0, T, SAME_NONZERO_PATTERN));
    PetscCall(MatDestroy(&U));
    PetscCall(MatDestroy(&T));
  }
  PetscCall(MatDestroy(&M));
  PetscCall(VecDestroy(&lambda));
  PetscCall(VecDestroy(&diagonal));
  PetscCall(VecDestroy(&rhs));
  PetscCall(VecDestroy(&sums));
  PetscFunctionReturn(0);
}

// Without symmetry the least-squares closure is one multiplier per row: S_ij t_i / Σ_j S_ij.
PetscErrorCode scaleRows(Mat S, Vec ones, Vec target, int64_t* emptyRows) {
  Vec scale;
  PetscScalar* s;
  const PetscScalar* t;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(target, &scale));
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
  PetscCall(VecDestroy(&scale));
  PetscFunctionReturn(0);
}

// ‖S − S_raw‖_F / ‖S_raw‖_F (the patterns differ: dropped and mirrored entries).
PetscErrorCode relativeChange(MPI_Comm comm, Mat S, Mat raw, double* change) {
  double sums[2] = {0, 0};
  PetscFunctionBeginUser;
  PetscCall(walkRows(S, raw, [&](PetscInt, PetscInt, double a, double b) {
    sums[0] += (a - b) * (a - b);
    sums[1] += b * b;
  }));
  PetscCall(allReduce(comm, sums, 2, MPI_SUM));
  *change = sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) : 0;
  PetscFunctionReturn(0);
}

// F = diag(1/A) S for this rank's rows, leaving out zeros; tiny negative entries are clipped.
PetscErrorCode extractRows(Mat S, const std::vector<double>& area, double largest,
                           formfactor::SparseRows* out, RepairReport* report) {
  PetscInt first, end;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(S, &first, &end));
  out->firstRow = first;
  out->rowStart.assign(1, 0);
  out->column.clear();
  out->value.clear();
  for (PetscInt row = first; row < end; ++row) {
    PetscInt n;
    const PetscInt* columns;
    const PetscScalar* values;
    PetscCall(MatGetRow(S, row, &n, &columns, &values));
    for (PetscInt k = 0; k < n; ++k) {
      if (values[k] == 0) continue;
      if (values[k] < 0) {
        if (-values[k] < kClip * largest) {
          ++report->negativeClipped;
          continue;
        }
        ++report->negativeKept;
      }
      out->column.push_back(columns[k]);
      out->value.push_back(values[k] / area[row - first]);
    }
    PetscCall(MatRestoreRow(S, row, &n, &columns, &values));
    out->rowStart.push_back(static_cast<int64_t>(out->column.size()));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode repair(MPI_Comm comm, const formfactor::SparseRows& rows,
                      const std::vector<double>& area, const RepairOptions& options,
                      formfactor::SparseRows* out, RepairReport* report) {
  const int64_t local = rows.rowCount();
  const bool dropping = options.dropThreshold > 0;
  Mat raw, S;
  Vec ones, target, areas;
  PetscFunctionBeginUser;
  // What dropping removes, and the global sizes.
  double counts[5] = {static_cast<double>(local), static_cast<double>(rows.nonzeros()), 0, 0, 0};
  for (int64_t r = 0; r < local; ++r) {
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      const double weight = area[r] * rows.value[k];
      counts[4] += weight;
      if (dropping && rows.value[k] < options.dropThreshold) {
        counts[2] += 1;
        counts[3] += weight;
      }
    }
  }
  PetscCall(allReduce(comm, counts, 5, MPI_SUM));
  const double patches = counts[0];
  auto bytesPerPatch = [&](double nonzeros) {
    return patches > 0 ? (nonzeros * (8 + 8) + 8 * (patches + 1)) / patches : 0.0;
  };
  report->nonzerosBefore = static_cast<int64_t>(counts[1]);
  report->bytesPerPatchBefore = bytesPerPatch(counts[1]);
  report->droppedNonzeroShare = counts[1] > 0 ? counts[2] / counts[1] : 0;
  report->droppedWeightShare = counts[4] > 0 ? counts[3] / counts[4] : 0;

  // The raw S and how far it is from symmetric.
  Mat rawT;
  PetscCall(assembleRows(comm, rows, &area, &raw, 0.0));
  PetscCall(MatTranspose(raw, MAT_INITIAL_MATRIX, &rawT));
  Defect defect;
  PetscCall(measureDefect(comm, raw, rawT, &defect));
  report->reciprocityDefect = defect.relative;
  report->maxPairDefect = defect.maxPair;
  report->oneSidedShare = defect.oneSided;

  // Targets t_i = A_i Σ_j F_ij of the raw rows, and the areas as a vector.
  PetscCall(MatCreateVecs(raw, &ones, &target));
  PetscCall(VecDuplicate(target, &areas));
  PetscCall(VecSet(ones, 1.0));
  PetscCall(MatMult(raw, ones, target));
  {
    PetscScalar* a;
    PetscCall(VecGetArray(areas, &a));
    for (int64_t r = 0; r < local; ++r) a[r] = area[r];
    PetscCall(VecRestoreArray(areas, &a));
  }

  // (a) drop, (b) symmetrise: (S + Sᵀ)/2 on the union of the patterns.
  if (dropping) {
    PetscCall(assembleRows(comm, rows, &area, &S, options.dropThreshold));
    if (options.reciprocity) {
      Mat St, kept;
      PetscCall(MatTranspose(S, MAT_INITIAL_MATRIX, &St));
      PetscCall(symmetricPart(comm, S, St, &kept));
      PetscCall(MatDestroy(&St));
      PetscCall(MatDestroy(&S));
      S = kept;
    }
  } else if (options.reciprocity) {
    PetscCall(symmetricPart(comm, raw, rawT, &S));
  } else {
    PetscCall(MatDuplicate(raw, MAT_COPY_VALUES, &S));
  }
  PetscCall(MatDestroy(&rawT));

  // (c) restore the row sums.
  PetscCall(closureError(S, ones, target, areas, &report->closureBefore));
  report->closureAfter = report->closureBefore;
  if (dropping || options.reciprocity) {
    if (options.reciprocity) {
      KSP ksp;
      PetscCall(createClosureSolver(comm, target, &ksp));
      for (int pass = 0; pass < kMaxLawsonPasses && report->closureAfter > kClosureTolerance;
           ++pass) {
        int64_t empty = 0;
        PetscCall(lawsonPass(S, ones, target, ksp, report, &empty));
        if (pass == 0) report->emptyRows = empty;
        PetscCall(closureError(S, ones, target, areas, &report->closureAfter));
        if (!report->converged) break;
      }
      PetscCall(KSPDestroy(&ksp));
    } else {
      PetscCall(scaleRows(S, ones, target, &report->emptyRows));
      PetscCall(closureError(S, ones, target, areas, &report->closureAfter));
    }
    double empty = static_cast<double>(report->emptyRows);
    PetscCall(allReduce(comm, &empty, 1, MPI_SUM));
    report->emptyRows = static_cast<int64_t>(empty);
  }

  PetscCall(relativeChange(comm, S, raw, &report->change));
  if (!options.reciprocity) {
    // (Symmetrised, S is symmetric bit for bit by construction: defectAfter = 0.)
    Mat St;
    Defect after;
    PetscCall(MatTranspose(S, MAT_INITIAL_MATRIX, &St));
    PetscCall(measureDefect(comm, S, St, &after));
    PetscCall(MatDestroy(&St));
    report->defectAfter = after.relative;
  }
  PetscCall(extractRows(S, area, defect.largest, out, report));
  double results[3] = {static_cast<double>(out->nonzeros()),
                       static_cast<double>(report->negativeClipped),
                       static_cast<double>(report->negativeKept)};
  PetscCall(allReduce(comm, results, 3, MPI_SUM));
  report->nonzerosAfter = static_cast<int64_t>(results[0]);
  report->negativeClipped = static_cast<int64_t>(results[1]);
  report->negativeKept = static_cast<int64_t>(results[2]);
  report->bytesPerPatchAfter = bytesPerPatch(results[0]);

  PetscCall(VecDestroy(&areas));
  PetscCall(VecDestroy(&target));
  PetscCall(VecDestroy(&ones));
  PetscCall(MatDestroy(&S));
  PetscCall(MatDestroy(&raw));
  PetscFunctionReturn(0);
}

}  // namespace

formfactor::SparseRows repairFormFactors(const formfactor::SparseRows& rows,
                                         const std::vector<double>& localArea,
                                         const RepairOptions& options, RepairReport& report,
                                         MPI_Comm comm) {
  if (static_cast<int64_t>(localArea.size()) != rows.rowCount()) {
    throw Error(exit_code::kFailure, "repairFormFactors: " + std::to_string(localArea.size()) +
                                         " areas for " + std::to_string(rows.rowCount()) + " rows");
  }
  if (!(options.dropThreshold >= 0)) {
    throw Error(exit_code::kUsage, "the drop threshold must be >= 0");
  }
  // The rows must be the contiguous blocks in rank order that PETSc's layout gives them.
  int64_t local = rows.rowCount(), first = 0;
  MPI_Exscan(&local, &first, 1, MPI_INT64_T, MPI_SUM, comm);
  int rank;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) first = 0;  // MPI_Exscan leaves rank 0's result undefined
  int misplaced = first != rows.firstRow;
  MPI_Allreduce(MPI_IN_PLACE, &misplaced, 1, MPI_INT, MPI_MAX, comm);
  if (misplaced) {
    throw Error(exit_code::kFailure,
                "repairFormFactors: the ranks' rows are not contiguous blocks in rank order");
  }
  report = RepairReport{};
  formfactor::SparseRows repaired;
  check(repair(comm, rows, localArea, options, &repaired, &report), "the form-factor repair");
  return repaired;
}

}  // namespace radiosity::solve
