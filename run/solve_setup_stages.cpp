// The stages of `radiosity solve` up to the first round (run/solve_pipeline.h): the outputs
// checked, the scene loaded and meshed, the run planned and restarted, the tracing prepared.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "core/xml_text.h"
#include "io/scene/scene.h"
#include "io/store/checkpoint.h"
#include "io/store/scene_file.h"
#include "io/store/xdmf.h"
#include "parallel/collective.h"
#include "run/checkpointing.h"
#include "run/derived_settings.h"
#include "run/memory_check.h"
#include "run/output_paths.h"
#include "run/solve_json.h"
#include "run/solve_pipeline.h"
#include "run/stage_reports.h"

namespace radiosity::run {

// Outputs that cannot be written, or would overwrite an input or a device, are refused now, not
// after the solve: every input (scene, job file, restart; the files the scene names once it is
// read) is one they must not be. (A checkpoint may be the file a restart reads: that is how a
// requeued job goes on.)
std::vector<std::string> SolvePipeline::givenInputs() const {
  return {request_.scene, std::filesystem::path(request_.scene).replace_extension(".mtl"),
          request_.jobFile, request_.thermal, request_.formfactorsFrom};
}

void SolvePipeline::checkOutputsFirst() {
  runCollectively(console_.comm(), [&] {
    const std::string sidecar = xdmfPathFor(request_.output);
    if (sidecar == request_.output)
      throw Error(exit_code::kUsage, request_.output +
                                         ": the result's XDMF sidecar takes the "
                                         "name with .xmf; name the result .h5");
    // The sidecar names the result: a name XML cannot hold would fail after the solve.
    if (!xmlHolds(std::filesystem::path(request_.output).filename().string()))
      throw Error(exit_code::kUsage, escapeXml(request_.output) +
                                         ": the name is not UTF-8 text XML can hold, and the "
                                         "result's XDMF sidecar must name it; rename it");
    std::vector<std::string> inputs = givenInputs();
    checkOutputs({request_.checkpoint}, inputs);
    inputs.push_back(request_.restart);
    checkOutputs({request_.output, sidecar}, inputs);
    checkOutputs({request_.output, sidecar, request_.checkpoint}, {});
    checkMpiIoOutputs({request_.output, request_.checkpoint});
  });
}

// The files the scene named (an OBJ's mtllib, whatever their names) are inputs too.
void SolvePipeline::checkOutputsAgainstScene() {
  if (request_.meshOnly) return;
  runCollectively(console_.comm(), [&] {
    checkOutputs({request_.output, xdmfPathFor(request_.output), request_.checkpoint},
                 scene_.sourceFiles);
  });
}

// --log-file, opened once it is known to be none of the run's inputs and outputs.
void SolvePipeline::openLogFile() {
  if (request_.logFile.empty()) return;
  runCollectively(console_.comm(), [&] {
    std::vector<std::string> inputs = givenInputs();
    inputs.push_back(request_.restart);
    inputs.insert(inputs.end(), scene_.sourceFiles.begin(), scene_.sourceFiles.end());
    checkOutputs({request_.logFile}, inputs);
    if (!request_.meshOnly)
      checkOutputs(
          {request_.logFile, request_.output, xdmfPathFor(request_.output), request_.checkpoint},
          {});
    if (console_.isRoot()) console_.logFile()->open(request_.logFile);
  });
}

// 1. Load the scene: every rank holds the whole geometry (an HDF5 scene read by all together).
void SolvePipeline::load() {
  stageStart_ = MPI_Wtime();
  solve::ScopedStage stage("Load scene");
  scene_ = loadScene(request_.scene, comm_);
  char loaded[96];
  std::snprintf(loaded, sizeof loaded, "load: %lld triangles in %.2f s from ",
                static_cast<long long>(scene_.triangleCount()), MPI_Wtime() - stageStart_);
  console_.info(loaded + request_.scene);
  checkOutputsAgainstScene();
  openLogFile();
  for (const std::string& warning : scene_.warnings) console_.warn(warning);
  mesh_.lengthUnit = request_.lengthUnit.empty() ? scene_.lengthUnit : request_.lengthUnit;
  if (!request_.thermal.empty()) applyThermalConditions();
  endStage("load");
}

// 2. Mesh: refine to the area bound (or to about --patches patches) and number the patches along
// a space-filling curve (the mesh stage, run/mesh_stage.h, as `study` meshes). A mesh that
// cannot fit in memory is refused before it is attempted.
void SolvePipeline::mesh() {
  mesh_.maxArea = request_.maxArea > 0 ? request_.maxArea : scene_.totalArea() / kAutoPatchDivisor;
  {
    char option[64];
    if (request_.patches > 0) {
      std::snprintf(option, sizeof option, "--patches %lld",
                    static_cast<long long>(request_.patches));
    } else {
      std::snprintf(option, sizeof option, "--max-area %g", mesh_.maxArea);
    }
    checkMeshFits(comm_, scene_.totalArea(), scene_.triangleCount(), request_.patches,
                  mesh_.maxArea, option);
  }
  solve::ScopedStage stage("Mesh");
  mesh_.input = meshInput(request_, scene_, mesh_.maxArea);
  if (takeCheckpointMesh()) {
    endStage("mesh");
    return;
  }
  MeshedScene meshed = meshScene({.console = console_,
                                  .scene = std::move(scene_),
                                  .maxArea = mesh_.maxArea,
                                  .patches = request_.patches,
                                  .cutContacts = request_.cutContacts,
                                  .surfaceShare = request_.maxArea > 0 ? 0 : kAutoSurfaceShare});
  scene_ = Mesh();  // (moved into the stage, which frees it once refined)
  mesh_.patches = std::move(meshed.patches);
  if (request_.patches > 0) mesh_.maxArea = meshed.meshing.areaBound;
  reportMeshing(console_, meshed.meshing, request_.patches, mesh_.maxArea);
  endStage("mesh");
}

// A run reusing F (--formfactors-from) takes the patches F is over from its checkpoint where
// they were made from the same scene with the same options (meshInput): no contacts cut and no
// refinement replayed, and F then belongs to its patches whatever this version's meshing would
// make. Not with --patches, whose area bound only meshing finds. False: mesh the scene.
bool SolvePipeline::takeCheckpointMesh() {
  if (request_.formfactorsFrom.empty() || request_.patches > 0 || request_.meshOnly) return false;
  CheckpointMesh saved;
  try {
    saved = readCheckpointMesh(comm_, request_.formfactorsFrom);
  } catch (const InputError& e) {
    throw notACheckpointToReuse(e);
  }
  if (saved.empty() || saved.input != mesh_.input) return false;
  const int64_t patches = static_cast<int64_t>(saved.triangles.size());
  std::optional<Mesh> mesh;
  runCollectively(console_.comm(), [&] {
    mesh = meshFromCheckpoint(request_.formfactorsFrom, std::move(saved), scene_);
  });
  if (!mesh) return false;
  scene_ = Mesh();
  mesh_.patches = std::move(*mesh);
  mesh_.taken = true;
  console_.info("mesh: " + std::to_string(patches) + " patches taken from " +
                request_.formfactorsFrom + ", made there from this scene with these options");
  return true;
}

// --mesh-only: the load and mesh times, nothing written.
int SolvePipeline::reportMeshOnly() {
  std::ostringstream times;
  times << "mesh only, nothing written; stage times (s): load " << attributes_.stageSeconds["load"]
        << " mesh " << attributes_.stageSeconds["mesh"];
  console_.info(times.str());
  attributes_.ranks = console_.ranks();
  recordOptionsUsed();
  if (console_.isJson())
    console_.json(solveJson({"", mesh_.patches.triangleCount(), &attributes_, peakMegabytes_}));
  return exit_code::kOk;
}

// The estimator, the one named or the one that serves the scene (the log says why), chosen on
// the first mesh; the options line; the bound of adaptive refinement.
void SolvePipeline::plan() {
  mesh_.patchCount = mesh_.patches.triangleCount();
  if (!plan_.estimator && !restartFrom().empty()) takeCheckpointEstimator();
  if (!plan_.estimator) {
    const formfactor::EstimatorChoice choice =
        request_.thermal.empty() ? formfactor::chooseEstimator(mesh_.patches) : thermalEstimator();
    plan_.estimator = choice.estimator;
    console_.info(std::string("form factors: no --estimator given: ") +
                  formfactor::estimatorName(choice.estimator) + ", as " + choice.reason);
  }
  if (request_.exactRowsAllowed) {
    const formfactor::RowsChoice rows = formfactor::chooseRows(mesh_.patches, plan_.rays);
    plan_.exactRows = rows.exact;
    console_.info("form factors: " + rows.reason);  // (why not, too: a finer mesh loses them)
  }
  enforceThermalBalance();
  console_.info(describeSettings(request_, plan_, mesh_.maxArea, console_.ranks()));
  maxPatches_ = patchBound(plan_.rays);
  if (request_.maxPatches <= 0 && (request_.refineRounds > 0 || request_.targetError > 0)) {
    char memory[32];
    std::snprintf(memory, sizeof memory, "%.3g GB", jobMemoryBytes(comm_) / 1e9);
    console_.info("refinement: at most " + std::to_string(maxPatches_) +
                  " patches for now (F at the rays asked fits in half of the " + memory +
                  " the job's nodes give it; each round's rows measure it again; --max-patches "
                  "sets a bound)");
  }
}

// Without --estimator, a run starting from a checkpoint samples as its run did: the estimator
// `auto` chooses depends on what emits, which other materials (temperatures, a light switched
// on) change, and a checkpoint's rows extended or reused must be of one estimator.
void SolvePipeline::takeCheckpointEstimator() {
  std::map<std::string, std::string> identity;
  try {
    identity = readCheckpointIdentity(comm_, restartFrom());
  } catch (const InputError& e) {
    throw notACheckpointToReuse(e);
  }
  const auto named = identity.find("estimator");
  if (named == identity.end()) return;
  const auto estimator = valueNamed(formfactor::kEstimatorNames, named->second);
  if (!estimator) return;  // (the identity check names it)
  plan_.estimator = *estimator;
  console_.info(std::string("form factors: no --estimator given: ") +
                formfactor::estimatorName(*estimator) + ", as " + restartFrom() +
                " sampled its form factors with it");
}

// A checkpoint's refusal, with what --formfactors-from takes when it was that option's file.
InputError SolvePipeline::notACheckpointToReuse(const InputError& e) const {
  if (request_.formfactorsFrom.empty()) return e;
  return InputError(std::string(e.what()) +
                    "; --formfactors-from takes the checkpoint a run wrote with --checkpoint "
                    "(it holds F as sampled, and the mesh's refinement rounds)");
}

// --restart: the mesh of the checkpoint's run, its first mesh refined by the rounds it had done.
void SolvePipeline::replayRefinement() {
  if (restartFrom().empty()) return;
  RefinementHistory history;
  try {
    history = readCheckpointRefinement(comm_, restartFrom());
  } catch (const InputError& e) {
    throw notACheckpointToReuse(e);
  }
  if (mesh_.taken) {  // (refined already: the rounds are only recorded)
    state_.refinement = std::move(history);
    return;
  }
  for (int r = 0; r < history.rounds(); ++r) {
    const std::vector<int64_t> marks = history.round(r);
    for (int64_t t : marks)
      if (t >= mesh_.patches.triangleCount())
        throw InputError(restartFrom() + ": corrupted checkpoint: refinement round " +
                         std::to_string(r + 1) + " splits patch " + std::to_string(t) +
                         " of a mesh of " + std::to_string(mesh_.patches.triangleCount()));
    refineMesh(marks, history.patchesAfter[r]);
    if (mesh_.patches.triangleCount() != history.patchesAfter[r])
      throw InputError(restartFrom() + ": corrupted checkpoint: refinement round " +
                       std::to_string(r + 1) + " gives " +
                       std::to_string(mesh_.patches.triangleCount()) + " patches, not " +
                       std::to_string(history.patchesAfter[r]));
    try {
      mergeMesh(history.merges(r));
    } catch (const Error& e) {
      throw InputError(restartFrom() + ": corrupted checkpoint: refinement round " +
                       std::to_string(r + 1) + ": " + e.what());
    }
  }
  // The rays each round took and the estimates behind them, as the run recorded them.
  state_.refinement.raysAfter = history.raysAfter;
  state_.refinement.estimateBefore = history.estimateBefore;
  if (history.rounds() > 0)
    console_.info("restart: the mesh refined as in " + restartFrom() + " (" +
                  std::to_string(history.rounds()) + " rounds, " +
                  std::to_string(mesh_.patches.triangleCount()) + " patches)");
}

// The mesh's layout for a round (the first, or the first after a refinement): exact rows where
// the mesh allows; F refused if it cannot fit in memory; then the tracing stage
// (run/tracing_stage.h, as `study` lays out its meshes): the scene's BVH; this rank's rows, a
// block cut where the measured work is even (run/rank_balance.h), which does not change the
// answer; the patches that see nothing; this rank's patches' data.
void SolvePipeline::layOut() {
  mesh_.patchCount = mesh_.patches.triangleCount();
  state_.patchCount = mesh_.patchCount;
  if (request_.exactRowsAllowed && state_.refinement.rounds() > 0) {
    const bool exact = formfactor::chooseRows(mesh_.patches, plan_.rays).exact;
    if (exact != plan_.exactRows)
      console_.info(exact ? "form factors: exact rows (the refined mesh allows them)"
                          : "form factors: rows sampled (too many patches now for exact rows)");
    plan_.exactRows = exact;
  }
  plan_.pairsOnce = storesPairsOnce(request_, plan_, mesh_.patches);
  // A sampled row has at most an entry per ray; an exact row an entry per patch it faces.
  // After a refinement round, by the nonzeros per row the rows measured (patchBound): the bound
  // of the rays alone is many times what rows hold where a patch sees a room, not the scene.
  const int64_t rayColumns = plan_.rays * formfactor::raysPerSample(*plan_.estimator);
  const int64_t columns =
      plan_.exactRows ? (plan_.pairsOnce ? mesh_.patchCount / 2 + 1 : mesh_.patchCount)
      : formFactors_.nonzerosPerRow > 0
          ? std::min(rayColumns,
                     static_cast<int64_t>(std::ceil(1.25 * formFactors_.nonzerosPerRow *
                                                    static_cast<double>(plan_.rays) /
                                                    static_cast<double>(formFactors_.rays))))
          : rayColumns;
  checkFormFactorsFit(comm_, mesh_.patchCount, columns,
                      storesSinglePrecision(request_, plan_, mesh_.patches) ? kBytesPerSingleNonzero
                                                                            : kBytesPerNonzero,
                      plan_.exactRows
                          ? "exact rows (an entry per patch a row; --exact-rows off samples "
                            "rays instead)"
                          : "--rays " + std::to_string(plan_.rays));
  state_.identity = runIdentity(request_, plan_, mesh_.patches, mesh_.maxArea);
  // Surroundings above 0 K are of the materials: a checkpoint solved with others is solved again.
  if (thermal_.conditions.surroundingsTemperature > 0) {
    char surroundings[60];
    std::snprintf(surroundings, sizeof surroundings, ", surroundings %.17g K",
                  thermal_.conditions.surroundingsTemperature);
    state_.identity[kMaterials] += surroundings;
  }
  // Traced in the scene's own frame (core/mesh.h, TracingFrame), so that the answer at any
  // scale is the answer at scale 1; the result file gets the user's coordinates back.
  mesh_.worldVertices = mesh_.patches.vertices;
  state_.mesh = {mesh_.input, mesh_.worldVertices, mesh_.patches.triangles,
                 mesh_.patches.sourceFace};
  mesh_.frame = normaliseForTracing(mesh_.patches);
  // The blocks cut where the measured work is even (which needs the tracer).
  auto balanced = [&](const trace::SceneTracer& tracer) {
    const Balance balance = balanceRows(comm_, tracer, mesh_.patches,
                                        samplingOptions(request_, plan_), request_.balance);
    if (console_.ranks() > 1) console_.info(describeBalance(balance));
    return balance.blocks;
  };
  TracedRows laid = layOutRows({.console = console_,
                                .patches = mesh_.patches,
                                .threads = request_.threads,
                                .split = balanced});
  tracer_ = std::move(laid.tracer);
  mesh_.owned = laid.owned;
  mesh_.hidden = std::move(laid.hidden);
  reportHidden(console_, mesh_.patches, mesh_.hidden);
  mesh_.local = std::move(laid.local);
}

// Checkpoints: the run's state goes to --checkpoint at safe points (periodically, on a signal,
// at the end); --restart takes a state back, on any number of ranks, if it is this run's.
void SolvePipeline::restart() {
  const std::string& from = restartFrom();
  if (from.empty()) return;
  Checkpoint restored;
  try {
    restored = readCheckpoint(comm_, from, mesh_.owned.begin, mesh_.owned.end);
  } catch (const InputError& e) {
    throw notACheckpointToReuse(e);
  }
  if (request_.targetError > 0 || !request_.formfactorsFrom.empty()) {
    // a round of --target-error may have raised the rays (its rows, or a refinement round's
    // record where a stop came before its rows); --formfactors-from takes them all
    int64_t most = 0;
    for (int64_t samples : restored.rows.rowSamples) most = std::max(most, samples);
    MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_INT64_T, MPI_MAX, comm_);
    if (request_.formfactorsFrom.empty()) most = std::max(most, state_.refinement.lastRays());
    if (most != plan_.rays && (most > plan_.rays || !request_.formfactorsFrom.empty())) {
      console_.info("restart: " + std::to_string(most) + " rays per patch, as " + from +
                    (request_.formfactorsFrom.empty() ? "'s round of --target-error had them"
                                                      : "'s rows have them"));
      plan_.rays = most;
      maxPatches_ = patchBound(most);  // (as the round that raised them set it)
    }
  }
  bool otherMaterials = false;
  runCollectively(console_.comm(), [&] {
    otherMaterials = checkResumable(from, restored, state_.identity, mesh_.patchCount, plan_.rays);
  });
  reportRestart(console_, from, restored, mesh_.patchCount, plan_.rays);
  solved_.resume = resumableProgress(restored, plan_.rays, comm_);
  if (otherMaterials || !request_.formfactorsFrom.empty())
    reuseFormFactors(restored, otherMaterials);
  state_.rows = std::move(restored.rows);
  state_.rowBalance = std::move(restored.rowBalance);
}

// A checkpoint's form factors for other materials (reflectance, emission, thermal conditions),
// or by --formfactors-from: F depends on the geometry only. Its rows must be complete (rows
// begun under other emitters and finished under these would mix two estimators), no rays are
// added, and its solve is not this one: its B is only where each channel starts.
void SolvePipeline::reuseFormFactors(const Checkpoint& saved, bool otherMaterials) {
  int64_t incomplete = 0;
  for (int64_t samples : saved.rows.rowSamples) incomplete += samples != plan_.rays;
  incomplete +=
      static_cast<int64_t>(mesh_.owned.size()) - static_cast<int64_t>(saved.rows.rowSamples.size());
  MPI_Allreduce(MPI_IN_PLACE, &incomplete, 1, MPI_INT64_T, MPI_SUM, comm_);
  const std::string& from = restartFrom();
  if (incomplete > 0)
    throw InputError(from + ": its form factors are not complete (" + std::to_string(incomplete) +
                     " rows short of " + std::to_string(plan_.rays) +
                     " rays): finish that run (--restart with its own materials) before its "
                     "form factors serve others");
  if (solved_.resume)
    for (int& state : solved_.resume->channelState)
      state = otherMaterials && state == 2 ? 1 : state;
  if (otherMaterials && solved_.resume) solved_.resume->history = SolveHistory{};
  console_.info("form factors: reused from " + from + " (" + std::to_string(plan_.rays) +
                " rays per patch; no rays cast for " + "them)" +
                (otherMaterials ? ", for other materials than its own: the solve runs again" : ""));
}

// The solver's options and call-backs, for every round.
void SolvePipeline::prepareTracing() {
  if (request_.solver) solved_.options.solver = *request_.solver;
  // Without --rtol, each channel stops where the solver's error is a tenth of the sampling
  // error (solve::Options::adaptiveRtol).
  solved_.options.rtol = request_.rtol > 0 ? request_.rtol : solve::kFirstAdaptiveRtol;
  solved_.options.adaptiveRtol = request_.rtol <= 0;
  solved_.options.calibrate = [this](const std::vector<Rgb>& radiosity) {
    return calibrate(radiosity);
  };
  solved_.options.discretisation = [this](const std::vector<Rgb>& irradiance,
                                          std::vector<Rgb>& error, std::vector<Rgb>& variance) {
    estimateDiscretisation(irradiance, error, variance);
  };
  solved_.options.safePoint = [this] { return safePoints_->poll(); };
  if (!console_.isQuiet())
    solved_.options.progress = [this](const std::string& line) { console_.info(line); };
  solved_.options.save = [this](const SolveProgress& progress, formfactor::SplitRows* rows) {
    saveProgress(progress, rows);
  };
}

}  // namespace radiosity::run
