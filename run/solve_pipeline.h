// `radiosity solve` as a pipeline: one object holds the run's state (the scene, the patches, this
// rank's rows of F, the solution, the stage times) and each stage is a method that takes the state
// one step further. run() calls the stages in order (run/solve_pipeline.cpp); the stages up to
// the first round are in run/solve_setup_stages.cpp, those of each round in
// run/solve_round_stages.cpp, each file in the order run() calls them.
#pragma once

#include <mpi.h>

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "formfactor/group_factors.h"
#include "io/store/checkpoint.h"
#include "io/store/collective_outputs.h"
#include "io/store/result.h"
#include "partition/partition.h"
#include "run/console.h"
#include "run/formfactor_stage.h"
#include "run/mesh_stage.h"
#include "run/rank_balance.h"
#include "run/run_plan.h"
#include "run/safe_points.h"
#include "run/solve_json.h"
#include "run/solve_request.h"
#include "run/tracing_stage.h"
#include "solve/discretisation_error.h"
#include "solve/error_calibration.h"
#include "solve/solve.h"
#include "thermal/thermal.h"

namespace radiosity::run {

class SolvePipeline {
 public:
  SolvePipeline(const SolveRequest& request, const Console& console);
  SolvePipeline(const SolvePipeline&) = delete;
  SolvePipeline& operator=(const SolvePipeline&) = delete;

  /// Runs every stage; returns the exit code (every rank the same) or throws radiosity::Error.
  int run();

 private:
  // The stages, in the order run() calls them.
  /// The files the options name as inputs: the scene (and the MTL beside it), the job file,
  /// the thermal conditions, --formfactors-from's checkpoint (not --restart's, which a
  /// checkpoint may be).
  std::vector<std::string> givenInputs() const;
  void checkOutputsFirst();
  void checkOutputsAgainstScene();  ///< in load(), once the scene's own files are known
  void openLogFile();               ///< in load(), after the outputs' checks
  void load();
  void mesh();
  int reportMeshOnly();
  void plan();
  void takeCheckpointEstimator();
  bool takeCheckpointMesh();
  void replayRefinement();
  void layOut();
  void restart();
  void reuseFormFactors(const Checkpoint& saved, bool otherMaterials);
  InputError notACheckpointToReuse(const InputError& e) const;
  /// The checkpoint a run starts from: --restart, or --formfactors-from; empty: none.
  const std::string& restartFrom() const {
    return request_.restart.empty() ? request_.formfactorsFrom : request_.restart;
  }
  void prepareTracing();
  void sample();
  void chooseSolver();
  void repair();
  void solve();
  bool nextRound();
  /// Whether nextRound() may refine the mesh after this round's solve (which then needs the
  /// discretisation estimate's sources): not with F given, nor past --refine-rounds N or the
  /// default's one round (whether a round comes before that depends on the estimate itself).
  bool mayRefineNext() const;
  bool roundTowardsTarget();
  bool refinementStalled() const;
  bool refineByDefault();
  bool refineTowards(const std::string& why);
  bool refineRound(const std::string& why);
  bool refineRound(const std::string& why, const RunPlan& next, int64_t bound);
  /// Room under the patch bound for a marked patch's split and its closure.
  bool roomToRefine() const;
  void write();
  /// What the result and --json record of the options (recordOptions), at the end.
  void recordOptionsUsed();
  // A thermal run's parts (run/thermal_stages.cpp).
  struct HeatSums;
  void applyThermalConditions();
  static formfactor::EstimatorChoice thermalEstimator();
  void enforceThermalBalance();
  std::vector<Rgb> emissionWithSurroundings();
  void addSurroundingsIrradiance(std::vector<Rgb>& irradiance) const;
  void recordHeat();
  void reportHeat(const std::vector<HeatSums>& surface, double balance, double scale);
  void printHeat() const;

  // What the stages share.
  std::vector<int64_t> refineMesh(const std::vector<int64_t>& marks, int64_t budget);
  std::vector<int64_t> flatBisections(const std::vector<int64_t>& parentOf,
                                      const std::vector<int64_t>& sourceError) const;
  std::vector<std::array<int64_t, 2>> mergeMesh(const std::vector<int64_t>& vertices);
  int64_t patchBound(int64_t rays) const;
  /// Whether refinement stops where exact rows would give way to sampled ones
  /// (formfactor::exactRowsPatchBound): the default round of a run with exact rows.
  bool boundByExactRows() const;
  int64_t patchesThatFitAt(int64_t rays) const;
  void endStage(const char* name);
  void writeCheckpoint(const char* stage);
  Error stopped() const;
  // The solver's call-backs (solve::Options).
  solve::VarianceScale calibrate(const std::vector<Rgb>& radiosity);
  void estimateDiscretisation(const std::vector<Rgb>& irradiance, std::vector<Rgb>& error,
                              std::vector<Rgb>& variance);
  void saveRows(SampledRows& rows);
  void saveProgress(const SolveProgress& progress, formfactor::SplitRows* rows);
  solve::FormFactorRows formFactorsToSolve();
  solve::FormFactorRows balancedFormFactors(bool keepRows);

  /// What the run was asked for, as given (with the output named): never changed.
  const SolveRequest request_;
  /// What the run chose (the estimator, exact rows, the store's precision, reciprocity for CG)
  /// and each round's rays.
  RunPlan plan_;
  const Console& console_;
  const MPI_Comm comm_;
  const double startedAt_;       ///< MPI_Wtime at the start: --stop-after counts from here
  ResultAttributes attributes_;  ///< stage times as they come, the rest at the end
  double stageStart_ = 0;
  /// The largest rank's peak resident set (MB) by the end of each stage: where memory grows.
  std::map<std::string, double> peakMegabytes_;

  Mesh scene_;  ///< as loaded; freed once meshed

  /// What meshing and laying out made: the patches and what each rank knows of them.
  struct MeshResult {
    std::string input;  ///< the fingerprint of the scene and the meshing options (meshInput)
    /// The scene's length unit: --length-unit's, else the scene's; metres for a thermal run
    /// that states none; "": not known.
    std::string lengthUnit;
    bool taken = false;  ///< taken from --formfactors-from's checkpoint, refined as there
    Mesh patches;        ///< the refined mesh, in the tracing frame once planned
    double maxArea = 0;  ///< the area bound (chosen by --patches if given)
    int64_t patchCount = 0;
    partition::PatchRange owned;      ///< this rank's rows
    std::vector<Vec3> worldVertices;  ///< the patches' corners in the user's coordinates
    TracingFrame frame;               ///< how the traced patches relate to them
    /// 1 for each patch that sees nothing (under an object, inside a solid), every patch
    std::vector<uint8_t> hidden;
    OwnedPatches local;  ///< area, reflectance and emission of this rank's rows
  };
  MeshResult mesh_;
  int64_t maxPatches_ = 0;  ///< the most patches refinement may make (--max-patches)
  /// --target-error: the rays per patch at which a rays round measured the discretisation
  /// error again (0: none has); from there on it counts as measured.
  int64_t measuredAgainAt_ = 0;
  std::optional<SafePoints> safePoints_;
  std::unique_ptr<trace::SceneTracer> tracer_;

  /// The run's state as --checkpoint stores it: what ties it to this run, this rank's rows of F
  /// sampled so far (from a checkpoint or an earlier round, to extend; then this round's, kept
  /// for checkpoints and the next round) and the solve's progress when last saved.
  Checkpoint state_;

  /// What this round's form-factor stage made, and what the run keeps of the rounds before.
  struct FormFactorResult {
    formfactor::SplitRows store;  ///< this round's F as sampled (its one store) until solved
    std::vector<double> rowSums;  ///< this round's Σ_j F_ij per row, as sampled
    /// F repaired (--reciprocity, --drop-threshold), or kept for the result (--save-formfactors)
    formfactor::SparseRows repaired;
    /// The last solve gave F's store back (into state_.rows.values): --save-formfactors writes
    /// F from it instead of from `repaired`.
    bool storeHandedBack = false;
    /// A thermal run's sampled F is balanced (solve::balanceColumns) before the solve, so that
    /// a closed enclosure's heat rates sum to 0 (enforceThermalBalance).
    bool balanceColumns = false;
    /// The mean nonzeros per row of the last round sampled, and its rays per patch (0: none).
    double nonzerosPerRow = 0;
    int64_t rays = 0;
    std::vector<int64_t> rowSumHistogram;
    GroupFactors groups;  ///< between the scene's labels (formfactor/group_factors.h)
  };
  FormFactorResult formFactors_;

  /// What the solve stage made, and where the next solve goes on from.
  struct SolveResult {
    solve::Options options;
    std::string solverChoice;  ///< why the solver was chosen, if it was not named
    solve::CalibrationReport calibration;
    solve::DiscretisationReport discretisation;
    solve::Report report;
    LocalSolution solution;
    std::optional<SolveProgress> resume;  ///< where the solve goes on from
  };
  SolveResult solved_;

  /// A thermal run's conditions and what it made of them (run/thermal_stages.cpp).
  struct ThermalResult {
    /// --thermal: the boundary conditions and, per label of the scene, its table.
    thermal::BoundaryConditions conditions;
    std::vector<int> conditionOfLabel;
    /// Per row of this round: what the surroundings send into it, (1 − Σ_j F_ij) σT_amb⁴
    /// (W/m²); empty where the surroundings are at 0 K (emissionWithSurroundings).
    std::vector<double> surroundingsIrradiance;
    double metresPerUnit = 1;  ///< the scene's length unit in metres (a thermal run's SI)
    HeatSummary heat;          ///< the rates and balance (reportHeat)
    bool misBalanceWarned = false;
  };
  ThermalResult thermal_;
};

}  // namespace radiosity::run
