// solve: assembles F once as a PETSc MPIAIJ matrix and solves (I − diag(ρ_c) F) B_c = E_c per
// colour channel with a PETSc KSP. PETSc stays behind this header. Collective on the
// communicator PETSc was initialised with (PETSC_COMM_WORLD).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "core/run_state.h"
#include "core/vec3.h"
#include "formfactor/formfactor.h"
#include "io/store/result.h"
#include "solve/solver.h"

namespace radiosity::solve {

/// Gives glibc back its use of mmap for large blocks and its return of freed memory, which a
/// library loaded with PETSc turns off (the Runtime calls it first).
void returnFreedMemory();
/// Hands the heap's free pages back to the system (between stages and before the error
/// estimates, not during sampling).
void releaseFreedHeap();

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

/// The PETSc options given but never queried (PETSc's -options_left): misspelt, or meant for a
/// solver that did not run. Collective.
std::vector<std::string> unusedPetscOptions();

/// Refuses (exit code 2) PETSc options that the solve's KSP could not be set up with: an unknown
/// -ksp_type or -pc_type, a value that is not a number. Tried on a one-row system before any
/// work, on each rank alone (every rank has the same options).
void checkKrylovOptions();

/// Per channel, what the two parts of the variance model are multiplied by: true variance of a
/// row's H ≈ indirect × model indirect + direct × model direct.
struct VarianceScale {
  std::array<double, 3> indirect{1, 1, 1}, direct{1, 1, 1};
};

/// The collective decision taken at a safe point (once per iteration of every solver).
enum class SafePointAction { kContinue, kSave, kStop };

struct Options {
  Solver solver = Solver::kGmres;
  /// The channels the run's result has: 1 (thermal) names its one channel "grey" in messages
  /// and says nothing of the other two, which are copies of it.
  int channels = 3;
  /// Patches left out as hidden (ρ = 0 there: nothing reaches them), over all ranks: the log
  /// tells them from black ones.
  int64_t hiddenPatches = 0;
  double rtol = 1e-10;  ///< relative residual at which each channel stops
  /// Asked collectively at every iteration; kSave: save() the progress and go on; kStop: save()
  /// and stop (solveRadiosity then throws SolveStopped). Empty: never asked.
  std::function<SafePointAction()> safePoint;
  /// With `rows`: this rank's rows of F as sampled, the solve's one store of them when
  /// handBackRows is set (the tally rebuilt from it a piece at a time); null otherwise (the
  /// caller keeps its own copy for its checkpoints).
  std::function<void(const SolveProgress&, formfactor::SplitRows* rows)> save;
  /// Called on every rank now and then (every 10 s at most) with a line on the solve's progress
  /// (the channels, the iteration, the relative residual, the seconds). Empty: none.
  std::function<void(const std::string&)> progress;
  /// F is given as its one store (formfactor::SplitRows) and the solver leaves M as assembled
  /// (all but gauss-seidel and cg, which turn it into their explicit form): then PETSc works on
  /// the store's own arrays, which save() gets at a safe point and *rowsBack at the end (if not
  /// null), so that F is never held twice.
  bool handBackRows = false;
  formfactor::SplitRows* rowsBack = nullptr;
  /// Progress to resume from (channels done are taken as they are; the channel in progress
  /// starts from its iterate). Null: from the start.
  const SolveProgress* resume = nullptr;
  /// > 0: the samples behind each row of F, to estimate the sampling error of B
  /// (LocalSolution::radiosityStderr; see solve/sampling_error.h).
  int64_t samplesPerRow = 0;
  /// F is exact (formfactor::Options::exactRows): no sampling error, so no variance model and
  /// no calibration; the adaptive tolerance follows the estimated error (discretisation) instead.
  bool exactRows = false;
  /// Scales the two parts of the variance model (solve/sampling_error.h) to the estimator's
  /// real error, per channel. Called once, collectively, with this rank's rows of B. Empty:
  /// both scales 1.
  std::function<VarianceScale(const std::vector<Rgb>& radiosity)> calibrate;
  /// The discretisation error of each row's H (solve/discretisation_error.h), called once after
  /// the solve, collectively, with this rank's rows of H; returns the signed error of H and the
  /// variance of that estimate. The solve carries it through the bounces into an error of B
  /// (LocalSolution::radiosityDiscretisation). Empty: none estimated.
  std::function<void(const std::vector<Rgb>& irradiance, std::vector<Rgb>& error,
                     std::vector<Rgb>& variance)>
      discretisation;
  /// `rtol` is only where each channel starts: once the sampling error is known, a channel
  /// whose solver error (its a-posteriori bound, in the measure of io/store/light_error.h) is above
  /// a tenth of its sampling error is solved further, down to kFinestAdaptiveRtol at most. Needs
  /// samplesPerRow.
  bool adaptiveRtol = false;
};

/// Where the adaptive tolerance starts, and the tightest it goes.
inline constexpr double kFirstAdaptiveRtol = 1e-6;
inline constexpr double kFinestAdaptiveRtol = 1e-10;

/// Thrown on every rank by solveRadiosity when a safe point said kStop, after save().
class SolveStopped : public std::runtime_error {
 public:
  SolveStopped() : std::runtime_error("the solve stopped at a safe point") {}
};

/// The solver a scene should use when the user names none, and why.
struct SolverChoice {
  Solver solver = Solver::kGmres;
  std::string reason;
};

/// Picks from the largest row-scaled reflectance q = max_i ρ_i Σ_j F_ij and from whether F is
/// (made) reciprocal. Collective; every rank gets the same choice.
/// `rowSums`: this rank's Σ_j |F_ij| (formfactor::rowSums of F as sampled, all entries ≥ 0).
SolverChoice chooseSolver(const std::vector<double>& rowSums, const std::vector<Rgb>& reflectance,
                          bool reciprocal, MPI_Comm comm = MPI_COMM_WORLD);

struct Report {
  std::string solver;      ///< the solver that ran
  int64_t iterations = 0;  ///< summed over channels (southwell: batches)
  double residual = 0;  ///< largest final relative residual ‖E − A B‖/‖E‖ over channels
  bool converged = true;
  int channelsSolved = 0;
  std::string leftOut = "none";  ///< the work the scene did not need, and why
  // The work done, counted: unknowns iterated on (summed over channels), products with the
  // matrix (whole or a column batch) and the matrix entries they multiplied.
  int64_t unknowns = 0;
  int64_t matrixProducts = 0;
  int64_t nonzeroProducts = 0;
  /// Largest row-scaled reflectance q over the channels solved: Jacobi contracts by q per sweep.
  double contraction = 0;
  /// Bound on ‖B* − B‖∞ / ‖B‖∞ (largest over channels), from the final residual r:
  /// ‖B* − B‖∞ ≤ ‖D⁻¹ r‖∞ / (1 − q), D = diag(I − diag(ρ) F). Infinite when q ≥ 1.
  double errorBound = 0;
  /// Condition number estimate of the (preconditioned) operator, largest over the channels:
  /// from the Krylov method's extreme singular values (gmres, cg) or the bound (1 + q)/(1 − q).
  double conditionEstimate = 0;
  std::string conditionSource;
  SolveHistory history;  ///< every iteration of every channel solved
  /// With Options::samplesPerRow, per channel, in the measure of io/store/light_error.h: the
  /// estimated sampling error of B and of H.
  std::array<double, 3> samplingErrorB{}, samplingErrorH{};
  VarianceScale calibration;  ///< the scales the variance model was given
  /// With Options::discretisation, per channel: the estimated discretisation error of B, and
  /// the whole estimated error of B and of H (sampling and discretisation, each patch's
  /// combined in quadrature), in the same measure.
  std::array<double, 3> discretisationErrorB{}, errorB{}, errorH{};
  /// The largest of errorB (of samplingErrorB without a discretisation estimate): the headline
  /// figure (log, --target-error).
  double relativeStderr = 0;
  /// The largest of samplingErrorB and of discretisationErrorB: which one to reduce.
  double samplingShare = 0, discretisationShare = 0;
  /// Per channel: the solver's error bound ‖B* − B‖∞ in the same measure (an upper bound).
  std::array<double, 3> solverError{};
  /// With Options::adaptiveRtol: where the solve stopped and why.
  std::string toleranceNote;
};

/// F as solveRadiosity takes it over: its one store as sampled (lent to PETSc as it is, without a
/// copy, where F needs no row scaling), a tally (F_ij = sum / (2^32 · samples)), or values where F
/// was repaired.
using FormFactorRows =
    std::variant<formfactor::SparseRows, formfactor::SampleTally, formfactor::SplitRows>;

/// Throws Error(exit_code::kNumerical) when a channel does not converge or the system is
/// unphysical. `reflectance`, `emission` and `area` hold this rank's rows (those of `rows`).
/// `rows` is freed as soon as PETSc holds F, so that F is stored once during the solve: move
/// it in unless it is needed afterwards.
LocalSolution solveRadiosity(FormFactorRows rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& area, const Options& options,
                             Report& report);

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
