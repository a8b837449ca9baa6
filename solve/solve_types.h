// What the solve takes and gives (solveRadiosity, solve/solve.h): its options and call-backs,
// its report, and F in the forms it takes over. The solve's own files include this, not the
// face, so that no arrow points back up into solve.h.
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
  /// whose solver error (its a-posteriori bound, in the measure of measure/light_error.h) is above
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
  /// With Options::samplesPerRow, per channel, in the measure of measure/light_error.h: the
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

}  // namespace radiosity::solve
