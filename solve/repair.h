// The repairs of an estimated F before the solve: reciprocity and dropped entries with the row
// sums restored (repairFormFactors), and the columns balanced for a thermal run's heat rates
// (balanceColumns). Collective.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

#include "formfactor/formfactor.h"

namespace radiosity::solve {

/// What repairFormFactors() does to the estimated F.
struct RepairOptions {
  /// Symmetrise S = diag(A) F: S ← (S + Sᵀ)/2, so that A_i F_ij = A_j F_ji exactly.
  bool reciprocity = false;
  /// Drop the entries F_ij below this (0: keep all).
  double dropThreshold = 0;
};

/// Figures of a repair. S = diag(A) F; norms are Frobenius; closure is max_i |Σ_j F_ij − t_i|
/// with t_i the row's sum as estimated (before dropping). Every figure is global.
struct RepairReport {
  double reciprocityDefect = 0;  ///< ‖S − Sᵀ‖ / ‖S‖ of the raw estimate
  /// max |S_ij − S_ji| / max(S_ij, S_ji) over the pairs estimated on both sides
  double maxPairDefect = 0;
  double oneSidedShare = 0;  ///< share of the raw nonzeros whose transposed entry is zero
  /// ‖S − Sᵀ‖ / ‖S‖ of the result: 0 with reciprocity (symmetric bit for bit by construction)
  double defectAfter = 0;
  double droppedNonzeroShare = 0;  ///< share of the raw nonzeros dropped
  double droppedWeightShare = 0;   ///< share of Σ_ij S_ij dropped
  double change = 0;               ///< ‖S_new − S_raw‖ / ‖S_raw‖
  double closureBefore = 0;        ///< after dropping and symmetrising, before the closure repair
  double closureAfter = 0;
  int64_t nonzerosBefore = 0, nonzerosAfter = 0;
  /// Stored F per patch: nonzeros × (8-byte column + 8-byte value) plus 8-byte row pointers.
  double bytesPerPatchBefore = 0, bytesPerPatchAfter = 0;
  int64_t iterations = 0;  ///< CG iterations of the closure solve (all passes)
  bool converged = true;   ///< the closure solve converged
  /// Entries that the closure repair made negative (S_ij (1 + λ_i + λ_j) < 0): the tiny ones
  /// (|S'_ij| < 1e-12 max S) are clipped to 0, the others kept (and counted in negativeKept).
  int64_t negativeClipped = 0, negativeKept = 0;
  int64_t emptyRows = 0;  ///< rows left without entries but with a target > 0: not closable
};

/// What balanceColumns() did: Sinkhorn sweeps and the row sums' largest relative change.
struct BalanceReport {
  int iterations = 0;
  double columnDefectBefore = 0;  ///< max_j |Σ_i A_i F_ij − A_j r_j| / (A_j r_j), as sampled
  double rowDefectAfter = 0;      ///< max_i |Σ_j F'_ij − r_i| / r_i
  bool converged = false;         ///< rowDefectAfter below the tolerance within the sweeps
  std::vector<double> rowScale;   ///< u_i of this rank's rows: where a later balance may start
};

/// Scales F in place to F'_ij = u_i F_ij v_j (Sinkhorn's alternating row and column scaling of
/// S = diag(A) F) so that every column carries what reciprocity says it must,
/// Σ_i A_i F'_ij = A_j r_j with r the rows' sums as sampled (exact to round-off: the last step
/// scales the columns), while each row keeps its sum r_i to within 1e-5. Then Σ_i A_i q_i
/// = Σ_j A_j J_j (1 − r_j) for any J: a closed enclosure's heat rates balance to round-off. It
/// keeps F's pattern and its one store (the symmetrising repair widens the pattern by the
/// transpose's entries and copies F twice), at a few passes over the values a sweep.
/// `rows` holds this rank's rows of global ids [rows.firstRow, rows.endRow) with their global
/// columns (not lent to PETSc); `localArea` their areas. In a single-precision store the
/// balance holds to float round-off (1e-7), so thermal runs store doubles by default.
/// Collective on `comm`.
/// `start`: row factors to start from (an earlier balance of the same F, from its checkpoint:
/// then a sweep or two suffice); empty, of another size or not all finite and positive: 1.
BalanceReport balanceColumns(formfactor::SplitRows& rows, const std::vector<double>& localArea,
                             int64_t globalPatchCount, MPI_Comm comm,
                             const std::vector<double>& start = {});

/// Repairs estimated form factors (collective on `comm`). `rows` and `localArea` (A_i) hold
/// this rank's rows, contiguous blocks of global ids in rank order. In order:
///  (a) drops F_ij < dropThreshold;
///  (b) with `reciprocity`, S = diag(A) F becomes (S + Sᵀ)/2 (rows across ranks);
///  (c) if (a) or (b) ran, restores every row sum to its estimated value t_i = Σ_j F_ij (raw):
///      with reciprocity by Lawson's symmetric least-squares correction
///      S'_ij = S_ij (1 + λ_i + λ_j), (diag(S·1) + S) λ = diag(A) t − S·1 solved by CG with
///      point Jacobi; without it by scaling each row (the same least-squares problem without
///      the symmetry constraint).
/// Returns F with the same rows, columns ascending, zeros left out; the result depends on the
/// number of ranks only through the round-off of the CG's sums.
formfactor::SparseRows repairFormFactors(const formfactor::SparseRows& rows,
                                         const std::vector<double>& localArea,
                                         const RepairOptions& options, RepairReport& report,
                                         MPI_Comm comm = MPI_COMM_WORLD);

}  // namespace radiosity::solve
