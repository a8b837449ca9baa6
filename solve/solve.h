// solve: assembles F once as a PETSc MPIAIJ matrix and solves (I − diag(ρ_c) F) B_c = E_c per
// colour channel with a PETSc KSP. PETSc stays behind this header. Collective on the
// communicator PETSc was initialised with (PETSC_COMM_WORLD).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/io.h"

namespace radiosity::solve {

/// Starts MPI and PETSc and ends them in the right order (RAII, like deal.II's
/// MPI_InitFinalize). `argv` holds the program name and the PETSc options only.
class Runtime {
 public:
  Runtime(int argc, char** argv);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;
};

/// A named stage of the -log_view report, pushed for the lifetime of the object.
class ScopedStage {
 public:
  explicit ScopedStage(const char* name);
  ~ScopedStage();
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;
};

/// PETSc's options database says whether `name` (e.g. "-log_view") was given.
bool hasPetscOption(const char* name);

struct Options {
  std::string solver = "gmres";  ///< "jacobi" (Richardson + Jacobi) or "gmres"
  double rtol = 1e-10;           ///< relative residual at which each channel stops
};

struct Report {
  int64_t iterations = 0;  ///< summed over channels
  double residual = 0;  ///< largest final relative residual ‖E − A B‖/‖E‖ over channels
  bool converged = true;
  int channelsSolved = 0;
  std::string leftOut = "none";  ///< the channels that needed no solve of their own, and why
};

/// Throws Error(exit_code::kNumerical) when a channel does not converge or the system is
/// unphysical. `reflectance`/`emission` hold this rank's rows (those of `rows`).
LocalSolution solveRadiosity(const formfactor::SparseRows& rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const Options& options, Report& report);

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
