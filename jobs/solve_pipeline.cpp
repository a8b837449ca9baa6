// `radiosity solve`, top to bottom: load, mesh, plan, restart, sample the form factors, repair
// them, solve, and write the result; with --target-error the sample-to-solve stages run again
// with more rays. The state lives in the SolvePipeline (solve_pipeline.h); the pieces each stage
// is built from are in the files included below.
#include "jobs/solve_pipeline.h"

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>
#include <utility>

#include "core/xml_text.h"
#include "io/scene/scene.h"
#include "io/store/checkpoint.h"
#include "io/store/collective.h"
#include "io/store/scene_file.h"
#include "io/store/xdmf.h"
#include "jobs/checkpointing.h"
#include "jobs/memory_check.h"
#include "jobs/output_paths.h"
#include "jobs/solve_settings.h"
#include "jobs/stage_reports.h"
#include "jobs/test_hooks.h"
#include "jobs/version.h"

namespace radiosity::jobs {

int runSolve(const SolveSettings& settings, const Console& console) {
  return SolvePipeline(settings, console).run();
}

SolvePipeline::SolvePipeline(const SolveSettings& settings, const Console& console)
    : settings_(settings), console_(console), comm_(console.comm()), startedAt_(MPI_Wtime()) {
  if (settings_.output.empty()) settings_.output = defaultOutput(settings_.scene);
}

int SolvePipeline::run() {
  if (!settings_.meshOnly) checkOutputsFirst();
  // From here a signal only asks for a stop: loading and meshing go on to the first safe point,
  // where the checkpoint records what there is (a batch job's stop at any stage requeues).
  safePoints_.emplace(comm_, !settings_.checkpoint.empty() && !settings_.meshOnly,
                      settings_.checkpointEvery, settings_.stopAfter, startedAt_);
  load();
  stallForTests("load");
  mesh();
  stallForTests("mesh");
  if (settings_.meshOnly) return reportMeshOnly();
  plan();
  restart();
  prepareTracing();
  // Rounds of form factors and solve: one, or with --target-error as many as it takes, each
  // adding samples to the same rows (the sequence is extensible) and starting from the last B.
  do {
    sample();
    chooseSolver();
    repair();
    solve();
  } while (nextRound());
  write();
  return exit_code::kOk;
}

// Outputs that cannot be written, or would overwrite an input or a device, are refused now, not
// after the solve: every input (scene, job file, restart; the files the scene names once it is
// read) is one they must not be. (A checkpoint may be the file a restart reads: that is how a
// requeued job goes on.)
void SolvePipeline::checkOutputsFirst() {
  runCollectively(console_.comm(), [&] {
    const std::string mtl = std::filesystem::path(settings_.scene).replace_extension(".mtl");
    const std::string sidecar = xdmfPathFor(settings_.output);
    if (sidecar == settings_.output)
      throw Error(exit_code::kUsage, settings_.output +
                                         ": the result's XDMF sidecar takes the "
                                         "name with .xmf; name the result .h5");
    // The sidecar names the result: a name XML cannot hold would fail after the solve.
    if (!xmlHolds(std::filesystem::path(settings_.output).filename().string()))
      throw Error(exit_code::kUsage, escapeXml(settings_.output) +
                                         ": the name is not UTF-8 text XML can hold, and the "
                                         "result's XDMF sidecar must name it; rename it");
    checkOutputs({settings_.output, sidecar},
                 {settings_.scene, mtl, settings_.restart, settings_.jobFile});
    checkOutputs({settings_.checkpoint}, {settings_.scene, mtl, settings_.jobFile});
    checkOutputs({settings_.output, sidecar, settings_.checkpoint}, {});
    checkMpiIoOutputs({settings_.output, settings_.checkpoint});
  });
}

// The files the scene named (an OBJ's mtllib, whatever their names) are inputs too.
void SolvePipeline::checkOutputsAgainstScene() {
  if (settings_.meshOnly) return;
  runCollectively(console_.comm(), [&] {
    checkOutputs({settings_.output, xdmfPathFor(settings_.output), settings_.checkpoint},
                 scene_.sourceFiles);
  });
}

// 1. Load the scene: every rank holds the whole geometry (an HDF5 scene read by all together).
void SolvePipeline::load() {
  stageStart_ = MPI_Wtime();
  solve::ScopedStage stage("Load scene");
  scene_ = loadScene(settings_.scene, comm_);
  checkOutputsAgainstScene();
  for (const std::string& warning : scene_.warnings) console_.warn(warning);
  attributes_.lengthUnit = settings_.lengthUnit.empty() ? scene_.lengthUnit : settings_.lengthUnit;
  endStage("load");
}

// 2. Mesh: refine to the area bound (or to about --patches patches) and number the patches along
// a space-filling curve. A mesh that cannot fit in memory is refused before it is attempted.
void SolvePipeline::mesh() {
  maxArea_ = settings_.maxArea > 0 ? settings_.maxArea : scene_.totalArea() / kAutoPatchDivisor;
  {
    char option[64];
    if (settings_.patches > 0) {
      std::snprintf(option, sizeof option, "--patches %lld",
                    static_cast<long long>(settings_.patches));
    } else {
      std::snprintf(option, sizeof option, "--max-area %g", maxArea_);
    }
    checkMeshFits(comm_, scene_.totalArea(), scene_.triangleCount(), settings_.patches, maxArea_,
                  option);
  }
  solve::ScopedStage stage("Mesh");
  partition::MeshingReport meshing;
  runCollectively(console_.comm(), [&] {
    Contacts contacts;
    if (settings_.cutContacts) {
      const double start = MPI_Wtime();
      contacts = cutAlongContacts(scene_);
      if (contacts.cut)
        reportContacts(console_, contacts.report, contacts.edges.size(), MPI_Wtime() - start);
    }
    const partition::ContactEdges* edges = contacts.cut ? &contacts.edges : nullptr;
    Mesh refined = settings_.patches > 0
                       ? partition::refineToCount(scene_, settings_.patches, &meshing, edges)
                       : partition::refine(scene_, maxArea_, &meshing, edges);
    scene_ = Mesh();  // not needed any more: free it before the reordered copy
    patches_ = partition::orderAlongCurve(std::move(refined));
  });
  if (settings_.patches > 0) maxArea_ = meshing.areaBound;
  reportMeshing(console_, meshing, settings_.patches, maxArea_);
  endStage("mesh");
}

// --mesh-only: the load and mesh times, nothing written.
int SolvePipeline::reportMeshOnly() {
  std::ostringstream times;
  times << "mesh only, nothing written; stage times (s): load " << attributes_.stageSeconds["load"]
        << " mesh " << attributes_.stageSeconds["mesh"];
  console_.info(times.str());
  return exit_code::kOk;
}

// The estimator, the one named or the one that serves the scene (the log says why); the options
// line; F refused if it cannot fit in memory; the scene's BVH; and this rank's rows, a block cut
// where the measured work is even (jobs/rank_balance.h), which does not change the answer.
void SolvePipeline::plan() {
  patchCount_ = patches_.triangleCount();
  if (!settings_.estimator) {
    const formfactor::EstimatorChoice choice = formfactor::chooseEstimator(patches_);
    settings_.estimator = choice.estimator;
    console_.info(std::string("form factors: no --estimator given: ") +
                  formfactor::estimatorName(choice.estimator) + ", as " + choice.reason);
  }
  if (settings_.exactRowsAllowed) {
    const formfactor::RowsChoice rows = formfactor::chooseRows(patches_, settings_.raysPerPatch);
    settings_.exactRows = rows.exact;
    if (rows.exact) console_.info("form factors: " + rows.reason);
  }
  if (!settings_.quiet) console_.info(describeSettings(settings_, maxArea_, console_.ranks()));
  // MIS casts two rays a sample (formfactor.h); an exact row has an entry per patch it faces.
  checkFormFactorsFit(
      comm_, patchCount_,
      settings_.exactRows ? patchCount_
                          : settings_.raysPerPatch *
                                (settings_.estimator == formfactor::Estimator::kEmitterMis ? 2 : 1),
      settings_.exactRows ? "exact rows (an entry per patch a row; --exact-rows off samples "
                            "rays instead)"
                          : "--rays " + std::to_string(settings_.raysPerPatch));
  state_.identity = runIdentity(settings_, patches_, maxArea_);
  // Traced in the scene's own frame (core/mesh.h, TracingFrame), so that the answer at any
  // scale is the answer at scale 1; the result file gets the user's coordinates back.
  worldVertices_ = patches_.vertices;
  frame_ = normaliseForTracing(patches_);
  tracer_ = buildTracer(console_, patches_, settings_.threads);
  const Balance balance = balanceRows(comm_, *tracer_, patches_, samplingOptions(settings_),
                                      balanceModeNamed(settings_.balance));
  if (console_.ranks() > 1) console_.info(describeBalance(balance));
  owned_ = ownedRows(console_, balance.blocks);
  hidden_ = findHiddenPatches(comm_, *tracer_, patches_, owned_);
  reportHidden(console_, patches_, hidden_);
}

// Checkpoints: the run's state goes to --checkpoint at safe points (periodically, on a signal,
// at the end); --restart takes a state back, on any number of ranks, if it is this run's.
void SolvePipeline::restart() {
  state_.patchCount = patchCount_;
  if (settings_.restart.empty()) return;
  Checkpoint restored = readCheckpoint(comm_, settings_.restart, owned_.begin, owned_.end);
  runCollectively(console_.comm(), [&] {
    checkResumable(settings_.restart, restored, state_.identity, patchCount_,
                   settings_.raysPerPatch);
  });
  reportRestart(console_, settings_.restart, restored, patchCount_, settings_.raysPerPatch);
  resume_ = resumableProgress(restored, settings_.raysPerPatch, comm_);
  state_.rows = std::move(restored.rows);
}

// What every round traces and solves with: this rank's patches, and the solver's options and
// call-backs.
void SolvePipeline::prepareTracing() {
  local_ = ownedPatches(patches_, owned_);
  leaveOutHidden(local_, owned_, hidden_);
  if (settings_.solver) solveOptions_.solver = *settings_.solver;
  // Without --rtol, each channel stops where the solver's error is a tenth of the sampling
  // error (solve::Options::adaptiveRtol).
  solveOptions_.rtol = settings_.rtol > 0 ? settings_.rtol : solve::kFirstAdaptiveRtol;
  solveOptions_.adaptiveRtol = settings_.rtol <= 0;
  solveOptions_.calibrate = [this](const std::vector<Rgb>& radiosity) {
    return calibrate(radiosity);
  };
  solveOptions_.discretisation = [this](const std::vector<Rgb>& irradiance, std::vector<Rgb>& error,
                                        std::vector<Rgb>& variance) {
    estimateDiscretisation(irradiance, error, variance);
  };
  solveOptions_.safePoint = [this] { return safePoints_->poll(); };
  if (!settings_.quiet)
    solveOptions_.progress = [this](const std::string& line) { console_.info(line); };
  solveOptions_.save = [this](const SolveProgress& progress, formfactor::SampleTally* rows) {
    saveProgress(progress, rows);
  };
}

// 3. Form factors: this rank's rows, traced against the whole scene, in pieces with a safe point
// after each; rows sampled before (a checkpoint, an earlier round) are extended.
void SolvePipeline::sample() {
  formfactor::Statistics statistics;
  state_.progress = SolveProgress();  // this round's solve has not started
  {
    solve::ScopedStage stage("Form factors");
    ProgressReporter progress(console_, owned_.size(),
                              settings_.exactRows ? patchCount_ : settings_.raysPerPatch,
                              settings_.exactRows ? "pair factors" : "rays");
    std::function<void(int64_t)> callback;
    if (!settings_.quiet) callback = [&](int64_t done) { progress(done); };
    double cpuSeconds = 0;  // sampling only: ranks that wait at a safe point may spin
    try {
      tally_ = sampleOwnedRows(
          comm_, *tracer_, patches_, owned_, samplingOptions(settings_), std::move(state_.rows),
          *safePoints_, [this](SampledRows&& snapshot) { saveRows(std::move(snapshot)); },
          statistics, callback, &cpuSeconds);
    } catch (const solve::SolveStopped&) {
      throw stopped();
    }
    const std::string outcome =
        describeOutcome(comm_, cpuSeconds, static_cast<int64_t>(tally_.column.size()));
    if (console_.ranks() > 1 && !settings_.quiet) console_.info(outcome);
    rowSums_ = formfactor::rowSums(tally_);
    formfactor::addRowSums(rowSums_, statistics);
    endStage("formfactors");
    rowSumHistogram_ =
        reportFormFactors(console_, patches_, rowSums_, static_cast<int64_t>(tally_.sum.size()),
                          statistics, attributes_.stageSeconds["formfactors"]);
  }
  groups_ = formfactor::groupFactors(comm_, patches_, tally_, frame_.scale * frame_.scale);
  state_.rows = SampledRows();
  state_.rows.rowSamples.assign(owned_.size(), settings_.raysPerPatch);
}

// 3a. The solver: the one named, or one chosen for the scene (in the first round; the later
// ones keep it). CG needs a reciprocal F.
void SolvePipeline::chooseSolver() {
  if (!settings_.solver && solverChoice_.empty()) {
    const solve::SolverChoice choice =
        solve::chooseSolver(rowSums_, local_.reflectance, settings_.reciprocity, comm_);
    solveOptions_.solver = choice.solver;
    solverChoice_ = choice.reason;
    console_.info(std::string("solve: no --solver given: ") + solve::solverName(choice.solver) +
                  ", as " + choice.reason);
  }
  if (solve::needsReciprocity(solveOptions_.solver) && !settings_.reciprocity) {
    settings_.reciprocity = true;
    console_.info(std::string("solve: ") + solve::solverName(solveOptions_.solver) +
                  " needs a reciprocal F (cg: a symmetric form; chebyshev: real eigenvalues): "
                  "enforcing reciprocity (as with --reciprocity)");
  }
}

// 3b. Reciprocity and sparsification: symmetrise A_i F_ij = A_j F_ji and/or drop small F_ij,
// then restore every row's sum (Lawson's least-squares correction). Only when asked for.
void SolvePipeline::repair() {
  if (!settings_.reciprocity && settings_.dropThreshold <= 0) return;
  solve::ScopedStage stage("Repair form factors");
  solve::RepairReport repair;
  rows_ = solve::repairFormFactors(formfactor::toFormFactors(tally_), local_.area,
                                   {settings_.reciprocity, settings_.dropThreshold}, repair, comm_);
  endStage("repair");
  reportRepair(console_, repair, attributes_.stageSeconds["repair"]);
}

// 4. Solve (I − diag(ρ_c) F) B_c = E_c per channel, and estimate B's sampling error.
void SolvePipeline::solve() {
  solve::ScopedStage stage("Solve");
  solveOptions_.resume = resume_ ? &*resume_ : nullptr;
  solveOptions_.samplesPerRow = settings_.raysPerPatch;
  solveOptions_.exactRows = settings_.exactRows;
  try {
    solution_ = solve::solveRadiosity(formFactorsToSolve(), patchCount_, local_.reflectance,
                                      local_.emission, local_.area, solveOptions_, report_);
  } catch (const solve::SolveStopped&) {
    throw stopped();
  }
  endStage("solve");
  reportSolve(console_, report_, attributes_.stageSeconds["solve"]);
  reportCalibration(console_, calibration_, discretisation_, report_);
}

// --target-error: more rays while the estimated error is above the target and rays can bring it
// there; the discretisation error they cannot reduce. True: the next round is set up.
bool SolvePipeline::nextRound() {
  if (settings_.targetError <= 0 || report_.relativeStderr <= settings_.targetError) return false;
  char text[400];
  if (settings_.exactRows) {  // more rays would only repeat the same rows
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the rows of F are exact (no sampling error), so "
                  "the estimated error %.3g is the discretisation's, which rays cannot take away; "
                  "refine the mesh (a smaller --max-area, or more --patches)",
                  settings_.targetError, report_.relativeStderr);
    console_.warn(text);
    return false;
  }
  double reachable =
      std::pow(0.8 * settings_.targetError, 2) - std::pow(report_.discretisationShare, 2);
  // The discretisation estimate carries its own noise in quadrature, which its rays take away
  // (solve/discretisation_error.h: at 16 rays a patch it can be twice the error). Only a
  // well-measured one (256 rays a patch, from 1024 samples) is grounds to give up; before that,
  // aim the sampling error at half the target and measure again.
  const bool wellMeasured = solve::discretisationRays(settings_.raysPerPatch) >= 256;
  if (!wellMeasured) reachable = std::max(reachable, std::pow(0.4 * settings_.targetError, 2));
  if (reachable <= 0.04 * std::pow(settings_.targetError, 2)) {
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the estimated error is %.3g, of which the "
                  "discretisation error (%.3g) is more than rays can take away; refine the mesh "
                  "(a smaller --max-area, or more --patches)",
                  settings_.targetError, report_.relativeStderr, report_.discretisationShare);
    console_.warn(text);
    return false;
  }
  const int64_t next =
      nextRayCount(settings_.raysPerPatch, report_.samplingShare, std::sqrt(reachable) / 0.8);
  if (next <= settings_.raysPerPatch) {
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the estimated error is %.3g at %lld rays per "
                  "patch, the most allowed",
                  settings_.targetError, report_.relativeStderr,
                  static_cast<long long>(settings_.raysPerPatch));
    console_.warn(text);
    return false;
  }
  std::snprintf(text, sizeof text,
                "target error: estimated %.3g > %.3g at %lld rays per patch (sampling %.3g, "
                "discretisation %.3g); going on with %lld",
                report_.relativeStderr, settings_.targetError,
                static_cast<long long>(settings_.raysPerPatch), report_.samplingShare,
                report_.discretisationShare, static_cast<long long>(next));
  console_.info(text);
  resume_ = SolveProgress{{1, 1, 1}, solution_.radiosity, report_.history};  // the rows stay
  settings_.raysPerPatch = next;
  return true;
}

// 5. Write the result, each rank its own slab. The finished run's state goes first, and into
// place at once: a later --restart with more --rays adds to these rows, a run whose last
// checkpoint could not be written (a full disk) fails without leaving a result that looks
// complete, and whatever then stops the result (a full disk, a rank that dies) leaves the
// finished solve for --restart to write without solving again.
void SolvePipeline::write() {
  if (!settings_.checkpoint.empty()) {
    state_.progress = SolveProgress{{2, 2, 2}, solution_.radiosity, report_.history};
    writeCheckpoint("done");
  }
  CollectiveOutputs outputs(comm_);
  attributes_.ranks = console_.ranks();
  attributes_.raysPerPatch = settings_.raysPerPatch;
  attributes_.seed = settings_.seed;
  attributes_.solverChoice = solverChoice_;
  attributes_.software = softwareVersions();
  recordSolve(attributes_, report_, calibration_);
  attributes_.scene = settings_.scene;
  attributes_.options = describeSettings(settings_, maxArea_, console_.ranks());
  {
    solve::ScopedStage stage("Write result");
    // F goes to the file as it is, each rank its own rows.
    FormFactorOutput formFactors;
    formFactors.rowSumHistogram = rowSumHistogram_;
    formFactors.rowSumBinEdges = formfactor::rowSumBinEdges();
    if (settings_.saveFormFactors) formFactors.rows = &rows_;
    formFactors.groups = groups_;
    patches_.vertices = worldVertices_;
    solution_.hidden.assign(hidden_.begin() + owned_.begin, hidden_.begin() + owned_.end);
    // Left out of the solve: nothing reaches a hidden patch (B = E already, as ρ = 0 there).
    for (size_t i = 0; i < solution_.hidden.size(); ++i)
      if (solution_.hidden[i]) solution_.irradiance[i] = Rgb{0, 0, 0};
    try {
      stageResult(outputs, settings_.output, patches_, solution_, attributes_, formFactors);
    } catch (const Error& e) {
      if (settings_.checkpoint.empty()) throw;
      // The finished solve is not lost with the result: the checkpoint is in place already.
      throw Error(e.exitCode(), std::string(e.what()) + "; the checkpoint " + settings_.checkpoint +
                                    " holds the finished solve: run again with --restart " +
                                    settings_.checkpoint + " to write the result");
    }
    outputs.commit();
    endStage("write");
  }
  std::ostringstream times;
  times << "wrote " << settings_.output << "; stage times (s):";
  for (const char* stage : {"load", "mesh", "formfactors", "repair", "solve", "write"}) {
    auto seconds = attributes_.stageSeconds.find(stage);  // repair only with its options
    if (seconds != attributes_.stageSeconds.end()) times << " " << stage << " " << seconds->second;
  }
  console_.info(times.str());
  std::ostringstream memory;
  memory << "memory: peak resident set of the largest rank by the end of each stage (MB):";
  for (const char* stage : {"load", "mesh", "formfactors", "repair", "solve", "write"}) {
    auto peak = peakMegabytes_.find(stage);
    if (peak != peakMegabytes_.end())
      memory << " " << stage << " " << static_cast<long long>(peak->second);
  }
  console_.info(memory.str());
}

// A stage's wall time, the slowest rank's, summed over the rounds of --target-error.
void SolvePipeline::endStage(const char* name) {
  const double now = MPI_Wtime();
  attributes_.stageSeconds[name] += slowestRank(comm_, now - stageStart_);
  stageStart_ = now;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);  // ru_maxrss: the peak so far, in kB on Linux
  double megabytes = usage.ru_maxrss / 1024.0;
  MPI_Allreduce(MPI_IN_PLACE, &megabytes, 1, MPI_DOUBLE, MPI_MAX, comm_);
  peakMegabytes_[name] = megabytes;
}

// The run's state to --checkpoint, written and renamed at once.
void SolvePipeline::writeCheckpoint(const char* stage) {
  const double start = MPI_Wtime();
  state_.stage = stage;
  radiosity::writeCheckpoint(comm_, settings_.checkpoint, state_);
  reportCheckpoint(console_, settings_.checkpoint, stage, state_.rows.rowSamples,
                   slowestRank(comm_, MPI_Wtime() - start));
}

Error SolvePipeline::stopped() const {
  return Error(exit_code::kStoppedBySignal, "stopped by " + safePoints_->stopReason() +
                                                "; the run's state is in " + settings_.checkpoint +
                                                ": resume with --restart " + settings_.checkpoint);
}

solve::VarianceScale SolvePipeline::calibrate(const std::vector<Rgb>& radiosity) {
  calibration_ = solve::calibrateSamplingError(comm_, *tracer_, patches_, owned_,
                                               samplingOptions(settings_), radiosity);
  return calibration_.scale;
}

void SolvePipeline::estimateDiscretisation(const std::vector<Rgb>& irradiance,
                                           std::vector<Rgb>& error, std::vector<Rgb>& variance) {
  solve::estimateDiscretisationError(comm_, *tracer_, patches_, owned_, settings_.seed,
                                     solve::discretisationRays(settings_.raysPerPatch), irradiance,
                                     hidden_, error, variance, discretisation_);
}

// A checkpoint from inside the form-factor stage: the rows so far, and those of an earlier
// checkpoint not reached yet (a snapshot, freed once written).
void SolvePipeline::saveRows(SampledRows&& snapshot) {
  state_.rows = std::move(snapshot);
  writeCheckpoint("formfactors");
  state_.rows = SampledRows();
}

// A periodic or final checkpoint from inside the solve: the rows of F (`rows`, rebuilt by the
// solve, or the copy kept here) and the solve's progress.
void SolvePipeline::saveProgress(const SolveProgress& progress, formfactor::SampleTally* rows) {
  state_.progress = progress;
  if (rows) state_.rows.tally = std::move(*rows);
  writeCheckpoint("solve");
  if (rows) state_.rows.tally = formfactor::SampleTally();
  safePoints_->checkpointWritten();
}

// F for the solve, which frees it once PETSc holds it. The rows of F as sampled are needed
// again for checkpoints and the next round: PETSc's copy is the one store of them wherever its
// values give the sums back exactly and stay as assembled (the solve rebuilds the tally from
// them); otherwise (F repaired, a solver that works on M in place, sums too large for a double)
// a copy of the tally is kept here. --save-formfactors keeps F's values for the result.
solve::FormFactorRows SolvePipeline::formFactorsToSolve() {
  const bool repaired = settings_.reciprocity || settings_.dropThreshold > 0;
  const bool keepRows = !settings_.checkpoint.empty() || settings_.targetError > 0;
  const solve::Solver solver = solveOptions_.solver;
  const bool rebuild = keepRows && !repaired && solver != solve::Solver::kCg &&
                       solver != solve::Solver::kGaussSeidel &&
                       formfactor::valuesKeepTheSums(tally_);
  solveOptions_.rebuildTally = rebuild;
  solveOptions_.tallyBack = rebuild ? &state_.rows.tally : nullptr;
  if (keepRows && !rebuild) state_.rows.tally = tally_;
  if (settings_.saveFormFactors && !repaired) rows_ = formfactor::toFormFactors(tally_);
  if (repaired) {
    tally_ = formfactor::SampleTally();
    return settings_.saveFormFactors ? rows_ : std::move(rows_);
  }
  return std::move(tally_);
}

}  // namespace radiosity::jobs
