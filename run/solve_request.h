// What a run of `radiosity solve` is asked for (its options as the command line and the job file
// give them), with the names --help gives their values and the defaults' constants.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/enum_names.h"
#include "formfactor/estimator.h"
#include "run/balance_mode.h"
#include "solve/solver.h"

namespace radiosity::run {

/// How F's store holds its values (--formfactor-precision).
enum class ValuePrecision { kAuto, kSingle, kDouble };

/// What `radiosity solve` is asked to do: the scene, the outputs and every option, made once
/// from the command line and the job file (jobs/solve_options.cpp).
struct SolveRequest {
  std::string scene;
  std::string output;     ///< default: the scene's name with .h5, in the working directory
  double maxArea = 0;     ///< 0: automatic (total area / kAutoPatchDivisor)
  int64_t patches = 0;    ///< > 0: refine to about this many patches instead (excludes maxArea)
  bool meshOnly = false;  ///< stop after meshing: no form factors, no file (for timing)
  /// --contacts cut (true): triangles cut along the lines where others touch or cross them
  /// before refinement (partition::cutAtContacts); off: meshed as given (kContactsModes).
  bool cutContacts = true;
  int64_t raysPerPatch = 1024;
  uint64_t seed = 1;
  /// none: "auto", chosen for the scene (formfactor::chooseEstimator)
  std::optional<formfactor::Estimator> estimator;
  int threads = 1;
  /// --exact-rows auto (true): rows by closed forms where formfactor::chooseRows allows; off:
  /// always sampled (kExactRowsModes).
  bool exactRowsAllowed = true;
  /// --formfactor-precision: how F's store holds its values (storesSinglePrecision).
  ValuePrecision valuePrecision = ValuePrecision::kAuto;
  std::optional<solve::Solver> solver;  ///< none: chosen for the scene (solve::chooseSolver)
  double rtol = 0;  ///< 0: adaptive, a tenth of the sampling error (solve::Options::adaptiveRtol)
  bool reciprocity = false;      ///< symmetrise A_i F_ij = A_j F_ji, then restore the row sums
  double dropThreshold = 0;      ///< > 0: drop F_ij below it, then restore the row sums
  bool saveFormFactors = false;  ///< also write the rows of F to the result (/formfactors)
  std::string checkpoint;        ///< checkpoint file; empty: none (signals keep their default)
  double checkpointEvery = 600;  ///< seconds between periodic checkpoints; 0: none
  std::string lengthUnit;  ///< the scene's length unit, for the result's labels; empty: the scene's
  /// --thermal: a boundary-condition file (thermal/thermal.h); the run is then grey thermal
  /// radiation exchange in SI units, one channel. Empty: lighting.
  std::string thermal;
  double stopAfter = 0;  ///< seconds after the start to checkpoint and stop by (exit 75); 0: never
  std::string restart;   ///< checkpoint to resume from; empty: start afresh
  /// --formfactors-from: a checkpoint whose complete form factors serve this run (other
  /// materials allowed, no rays, no refinement); empty: none.
  std::string formfactorsFrom;
  std::string jobFile;  ///< the --config file the options came from; empty: none
  /// Adaptive refinement rounds after the first solve (partition::refineMarked), without
  /// --target-error (which decides its own rounds); -1 (auto): one round where the first solve's
  /// estimated error is mostly discretisation (kAutoRefine*), none otherwise.
  int refineRounds = -1;
  /// The most patches refinement may make; 0: what F at the rays asked fits in memory
  /// (patchesThatFit), said in the log.
  int64_t maxPatches = 0;
  double targetError = 0;  ///< > 0: add rays until B's estimated relative sampling error is below
  /// --balance: auto (by cost from 4 ranks up), cost (by a pilot's measured work) or count
  BalanceMode balance = BalanceMode::kAuto;
  std::string logFile;   ///< --log-file: the log also appended to this file (run/log_file.h)
  bool quiet = false;    ///< -q (or a job file's `quiet = true`): the console drops the log
  bool verbose = false;  ///< -v: the log adds the solver's and estimators' inner figures
};

/// --formfactor-precision's names for SolveRequest::valuePrecision, with what --help says of each.
inline constexpr NamedValue<ValuePrecision> kValuePrecisions[] = {
    {ValuePrecision::kAuto, "auto",
     "the default: single precision, 8 B a nonzero instead of 12, where rounding F to it moves "
     "B by less than a thousandth of the sampling error, and for exact rows of 4,096 patches or "
     "more (rounded keeping each row's sum); double otherwise (fewer exact rows, reflectance "
     "near 1, very many rays, gauss-seidel and cg)"},
    {ValuePrecision::kSingle, "single", "single wherever rows have under 2^18 rays"},
    {ValuePrecision::kDouble, "double", "always double"},
};

/// --contacts's names for SolveRequest::cutContacts, with what --help says of each.
inline constexpr NamedValue<bool> kContactsModes[] = {
    {true, "cut",
     "the default: every triangle is cut along the lines where another touches, "
     "rests on or passes through it, before refinement, so that no patch "
     "straddles a lit part and a hidden one; patches that see nothing are left "
     "out of the solve"},
    {false, "off", "the triangles as given"},
};

/// --exact-rows's names for SolveRequest::exactRowsAllowed, with what --help says of each.
inline constexpr NamedValue<bool> kExactRowsModes[] = {
    {true, "auto",
     "the default: rows of F by closed forms, without rays, where every pair of patches that "
     "face each other sees each other whole, i.e. a convex scene, and the patches are at most "
     "8 x the rays per patch; the log says when"},
    {false, "off", "always rays"},
};

/// --refine-rounds auto refines once when the first solve's estimated discretisation error is
/// above kAutoRefineAbove and more than kAutoRefineOver times its sampling error: then a round
/// that splits where that error comes from buys more accuracy than the same time spent on rays.
inline constexpr double kAutoRefineAbove = 0.02;
inline constexpr double kAutoRefineOver = 2;

/// Without --max-area, patches get at most this share of the scene's total area.
inline constexpr double kAutoPatchDivisor = 4000;
/// Without --max-area, this many patches are also shared equally among the smooth surfaces
/// (partition::refine's surfaceShare): a 1 m room on a 10^6 m² ground is meshed where its light
/// varies, not at 2 triangles a wall.
inline constexpr int64_t kAutoSurfaceShare = 1000;

}  // namespace radiosity::run
