// The subcommands of the `radiosity` program and the settings each reads. Options are declared
// and validated in one place (command_line.cpp); each command is a function of its settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "formfactor/estimator.h"
#include "jobs/balance_mode.h"
#include "jobs/console.h"
#include "render/render.h"
#include "solve/solver.h"

namespace radiosity::jobs {

/// How F's store holds its values (--formfactor-precision).
enum class ValuePrecision { kAuto, kSingle, kDouble };

struct SolveSettings {
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
  bool exactRows = false;  ///< chosen at the start of the run (SolvePipeline::plan)
  bool pairsOnce = false;  ///< exact rows stored once a pair, chosen per round (storesPairsOnce)
  /// --formfactor-precision: how F's store holds its values (storesSinglePrecision).
  ValuePrecision valuePrecision = ValuePrecision::kAuto;
  bool singlePrecision = false;         ///< chosen for each round's rows (storesSinglePrecision)
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
  bool quiet = false;    ///< -q (or a job file's `quiet = true`): the console drops the log
  bool verbose = false;  ///< -v: the log adds the solver's and estimators' inner figures
};

/// --formfactor-precision's names for SolveSettings::valuePrecision, with what --help says of each.
inline constexpr NamedValue<ValuePrecision> kValuePrecisions[] = {
    {ValuePrecision::kAuto, "auto",
     "the default: single precision, 8 B a nonzero instead of 12, where rounding F to it moves "
     "B by less than a thousandth of the sampling error, and for exact rows of 4,096 patches or "
     "more (rounded keeping each row's sum); double otherwise (fewer exact rows, reflectance "
     "near 1, very many rays, gauss-seidel and cg)"},
    {ValuePrecision::kSingle, "single", "single wherever rows have under 2^18 rays"},
    {ValuePrecision::kDouble, "double", "always double"},
};

/// --contacts's names for SolveSettings::cutContacts, with what --help says of each.
inline constexpr NamedValue<bool> kContactsModes[] = {
    {true, "cut",
     "the default: every triangle is cut along the lines where another touches, "
     "rests on or passes through it, before refinement, so that no patch "
     "straddles a lit part and a hidden one; patches that see nothing are left "
     "out of the solve"},
    {false, "off", "the triangles as given"},
};

/// --exact-rows's names for SolveSettings::exactRowsAllowed, with what --help says of each.
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

struct RenderSettings {
  std::string input;
  std::string output;
  int width = 512, height = 512;
  std::vector<double> eye, lookAt, up;  ///< empty, or x,y,z
  double fov = 40;
  double exposure = 0;
  bool flat = false;
  render::FalseColour falseColour = render::FalseColour::kNone;
  render::Scale scale = render::Scale::kAuto;
};

/// `radiosity study`: the error of B and H against a reference, and the run time, over a sweep
/// of settings (jobs/study/study_command.cpp).
struct StudySettings {
  std::string scene;
  std::string output;     ///< CSV, a row per setting
  std::string plot;       ///< SVG; empty: none
  std::string reference;  ///< a result file of the same scene and mesh; empty: exact
  std::vector<int64_t> rays{16, 32, 64, 128, 256, 512, 1024};
  std::vector<formfactor::Estimator> estimators = valuesIn(formfactor::kEstimatorNames);
  std::vector<double> rtols{1e-10};
  std::vector<double> maxAreas;  ///< empty: the solve's automatic bound
  solve::Solver solver = solve::Solver::kGmres;
  uint64_t seed = 1;
  int threads = 1;
  bool quiet = false;
};

/// `radiosity verify`: an independent path-traced reference of patch-averaged B on a random
/// sample of a result's patches, and the measured error of the result (jobs/verify_command.cpp).
struct VerifySettings {
  std::string input;           ///< result file (HDF5)
  int64_t patches = 200;       ///< patches sampled (reflecting ones), at most all of them
  int64_t paths = 16384;       ///< paths per sampled patch
  double tol = 0.05;           ///< exit 1 when the measured RMS relative error of B exceeds this
  int64_t maxBounces = 10000;  ///< a reference path is cut after this many bounces (counted)
  uint64_t seed = 1;
  int threads = 1;
  std::string csv;  ///< per sampled patch: the result's and the reference's B and their errors
};

/// `radiosity xdmf`: the XDMF sidecar of a result file (io/store/xdmf.h).
struct XdmfSettings {
  std::string input;   ///< result file (HDF5)
  std::string output;  ///< default: the result's name with .xmf
};

struct SceneSettings {
  std::string name;
  std::string output;
};

/// `radiosity export`: a result's group view factors and groups as text for other tools
/// (io/store/result_tables.h); at least one output.
struct ExportSettings {
  std::string input;            ///< result file (HDF5)
  std::string viewFactors;      ///< View3D's text layout, or CSV when the name ends in .csv
  std::string groupsCsv;        ///< a row per group
  std::string exchangeFactors;  ///< a thermal result's Gebhart factors, CSV, a row per pair
};

int runSolve(const SolveSettings& settings, const Console& console);  ///< jobs/solve_pipeline.cpp
int runRender(const RenderSettings& settings, const Console& console);
int runInfo(const std::string& path, const Console& console);
int runScene(const SceneSettings& settings, const Console& console);
int runStudy(const StudySettings& settings, const Console& console);
int runXdmf(const XdmfSettings& settings, const Console& console);
int runVerify(const VerifySettings& settings, const Console& console);
int runExport(const ExportSettings& settings, const Console& console);

/// Parses the program's own arguments (PETSc's were taken out before) and runs the chosen
/// command. Returns the exit code; every rank returns the same.
/// `petscWords`: the words main() set aside for PETSc (one dash and a letter); one that spells
/// an option of ours with one dash (`-rays 16`) is refused (exit 2), as PETSc would ignore it.
int runCommandLine(const std::vector<std::string>& arguments, const Console& console,
                   const std::vector<std::string>& petscWords = {});

}  // namespace radiosity::jobs
