// Reciprocity and sparsification of estimated form factors, through PETSc. S = diag(A) F is an
// MPIAIJ matrix (explicit zero diagonal, so that diag(S·1) + S is formed in place); dropping
// happens while assembling, symmetrising is MatTranspose and a row-by-row merge of S and Sᵀ
// into the union pattern (no further communication; repair_symmetry.cpp), and the closure
// repair is Lawson's least-squares correction S'_ij = S_ij (1 + λ_i + λ_j) with λ from a CG
// solve (repair_closure.cpp). The PETSc-style functions return PetscErrorCode;
// repairFormFactors() turns failures into exceptions.
#include <petscmat.h>

#include <string>
#include <utility>

#include "solve/assemble.h"
#include "solve/local_rows.h"
#include "solve/petsc_check.h"
#include "solve/petsc_handles.h"
#include "solve/repair_steps.h"
#include "solve/shared_system.h"
#include "solve/repair.h"

namespace radiosity::solve {

namespace {

/// A repaired entry below −kClip · max S is kept (and counted); one above is round-off: 0.
constexpr double kClip = 1e-12;

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
  PetscCall(forEachLocalRow(
      S, [&](PetscInt row, PetscInt n, const PetscInt* columns, const PetscScalar* values) {
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
        out->rowStart.push_back(static_cast<int64_t>(out->column.size()));
      }));
  PetscFunctionReturn(0);
}

// Stored F per patch: nonzeros × (8-byte column + 8-byte value) plus 8-byte row pointers.
double bytesPerPatch(double nonzeros, double patches) {
  return patches > 0 ? (nonzeros * (8 + 8) + 8 * (patches + 1)) / patches : 0.0;
}

// What dropping will remove, and the global sizes before the repair; *patches: the global count.
PetscErrorCode countBefore(MPI_Comm comm, const formfactor::SparseRows& rows,
                           const std::vector<double>& area, const RepairOptions& options,
                           RepairReport* report, double* patches) {
  const int64_t local = rows.rowCount();
  const bool dropping = options.dropThreshold > 0;
  PetscFunctionBeginUser;
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
  *patches = counts[0];
  report->nonzerosBefore = static_cast<int64_t>(counts[1]);
  report->bytesPerPatchBefore = bytesPerPatch(counts[1], *patches);
  report->droppedNonzeroShare = counts[1] > 0 ? counts[2] / counts[1] : 0;
  report->droppedWeightShare = counts[4] > 0 ? counts[3] / counts[4] : 0;
  PetscFunctionReturn(0);
}

// The vectors of the closure repair: ones, the targets t_i = A_i Σ_j F_ij of the raw rows, and
// the areas.
struct ClosureVectors {
  OwnedVec ones, target, areas;
};

PetscErrorCode closureVectors(Mat raw, const std::vector<double>& area, ClosureVectors* v) {
  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(raw, v->ones.out(), v->target.out()));
  PetscCall(VecDuplicate(v->target, v->areas.out()));
  PetscCall(VecSet(v->ones, 1.0));
  PetscCall(MatMult(raw, v->ones, v->target));
  PetscCall(fillValues(v->areas, area));
  PetscFunctionReturn(0);
}

// (a) drop, (b) symmetrise: (S + Sᵀ)/2 on the union of the patterns; S = the raw S otherwise.
PetscErrorCode dropAndSymmetrise(MPI_Comm comm, const formfactor::SparseRows& rows,
                                 const std::vector<double>& area, const RepairOptions& options,
                                 Mat raw, Mat rawT, OwnedMat& S) {
  PetscFunctionBeginUser;
  if (options.dropThreshold > 0) {
    PetscCall(assembleRows(comm, rows, &area, S.out(), options.dropThreshold));
    if (options.reciprocity) {
      OwnedMat St, kept;
      PetscCall(MatTranspose(S, MAT_INITIAL_MATRIX, St.out()));
      PetscCall(symmetricPart(comm, S, St, kept.out()));
      S = std::move(kept);
    }
  } else if (options.reciprocity) {
    PetscCall(symmetricPart(comm, raw, rawT, S.out()));
  } else {
    PetscCall(MatDuplicate(raw, MAT_COPY_VALUES, S.out()));
  }
  PetscFunctionReturn(0);
}

// The figures of the repaired S: its change from the raw S, and its defect.
PetscErrorCode measureRepaired(MPI_Comm comm, Mat S, Mat raw, const RepairOptions& options,
                               RepairReport* report) {
  PetscFunctionBeginUser;
  PetscCall(relativeChange(comm, S, raw, &report->change));
  if (!options.reciprocity) {
    // (Symmetrised, S is symmetric bit for bit by construction: defectAfter = 0.)
    OwnedMat St;
    Defect after;
    PetscCall(MatTranspose(S, MAT_INITIAL_MATRIX, St.out()));
    PetscCall(measureDefect(comm, S, St, &after));
    report->defectAfter = after.relative;
  }
  PetscFunctionReturn(0);
}

// F out of the repaired S (`largest`: the raw S's largest entry, for the clipping), and its sizes
// over the `patches` of all ranks.
PetscErrorCode extractRepaired(MPI_Comm comm, Mat S, const std::vector<double>& area,
                               double largest, double patches, formfactor::SparseRows* out,
                               RepairReport* report) {
  PetscFunctionBeginUser;
  PetscCall(extractRows(S, area, largest, out, report));
  double results[3] = {static_cast<double>(out->nonzeros()),
                       static_cast<double>(report->negativeClipped),
                       static_cast<double>(report->negativeKept)};
  PetscCall(allReduce(comm, results, 3, MPI_SUM));
  report->nonzerosAfter = static_cast<int64_t>(results[0]);
  report->negativeClipped = static_cast<int64_t>(results[1]);
  report->negativeKept = static_cast<int64_t>(results[2]);
  report->bytesPerPatchAfter = bytesPerPatch(results[0], patches);
  PetscFunctionReturn(0);
}

PetscErrorCode repair(MPI_Comm comm, const formfactor::SparseRows& rows,
                      const std::vector<double>& area, const RepairOptions& options,
                      formfactor::SparseRows* out, RepairReport* report) {
  OwnedMat raw, rawT, S;
  ClosureVectors v;
  double patches = 0;
  PetscFunctionBeginUser;
  PetscCall(countBefore(comm, rows, area, options, report, &patches));

  // The raw S and how far it is from symmetric.
  PetscCall(assembleRows(comm, rows, &area, raw.out(), 0.0));
  PetscCall(MatTranspose(raw, MAT_INITIAL_MATRIX, rawT.out()));
  Defect defect;
  PetscCall(measureDefect(comm, raw, rawT, &defect));
  report->reciprocityDefect = defect.relative;
  report->maxPairDefect = defect.maxPair;
  report->oneSidedShare = defect.oneSided;

  PetscCall(closureVectors(raw, area, &v));
  PetscCall(dropAndSymmetrise(comm, rows, area, options, raw, rawT, S));
  rawT.reset();

  // (c) restore the row sums.
  PetscCall(closureError(S, v.ones, v.target, v.areas, &report->closureBefore));
  report->closureAfter = report->closureBefore;
  if (options.dropThreshold > 0 || options.reciprocity) {
    PetscCall(restoreRowSums(comm, S, v.ones, v.target, v.areas, options.reciprocity, report));
  }
  PetscCall(measureRepaired(comm, S, raw, options, report));
  PetscCall(extractRepaired(comm, S, area, defect.largest, patches, out, report));
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
