// `radiosity solve`, top to bottom: load, mesh, plan, restart, sample the form factors, repair
// them, solve, and write the result; with --target-error the sample-to-solve stages run again
// with more rays. The state lives in the SolvePipeline (solve_pipeline.h); run() and the end of
// the run are here, the stages up to the first round in run/solve_setup_stages.cpp, the
// rounds' stages in run/solve_round_stages.cpp.
#include "run/solve_pipeline.h"

#include <sys/resource.h>

#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/shown_text.h"
#include "formfactor/group_factors.h"
#include "io/store/checkpoint.h"
#include "parallel/collective.h"
#include "run/checkpointing.h"
#include "run/derived_settings.h"
#include "run/request_options.h"
#include "run/solve_json.h"
#include "run/stage_reports.h"
#include "run/test_hooks.h"
#include "run/version.h"

namespace radiosity::run {

int runSolve(const SolveRequest& request, const Console& console) {
  if (request.logFile.empty()) return SolvePipeline(request, console).run();
  // (opened by the pipeline once its path is checked: openLogFile)
  const Console logged = console.loggingTo(std::make_shared<LogFile>());
  try {
    return SolvePipeline(request, logged).run();
  } catch (const Error& e) {
    if (logged.isRoot() && logged.logFile()->isOpen())
      logged.logFile()->write(failureLine(e.exitCode(), e.what()));
    throw;
  }
}

namespace {

SolveRequest withOutputNamed(SolveRequest request) {
  if (request.output.empty()) request.output = defaultOutput(request.scene);
  return request;
}

}  // namespace

SolvePipeline::SolvePipeline(const SolveRequest& request, const Console& console)
    : request_(withOutputNamed(request)),
      plan_(initialPlan(request)),
      console_(console),
      comm_(console.comm()),
      startedAt_(MPI_Wtime()) {
  // (an option the command line cannot tie to another's value)
  if (!request_.formfactorsFrom.empty() && request_.refineRounds > 0)
    throw Error(exit_code::kUsage,
                "--formfactors-from reuses F as it is: no --refine-rounds (they sample anew)");
}

int SolvePipeline::run() {
  // A typo in a PETSc option is refused before F is sampled, not found by the solve after.
  if (!request_.meshOnly && request_.solver != solve::Solver::kSouthwell)
    solve::checkKrylovOptions();
  if (!request_.meshOnly) checkOutputsFirst();
  // From here a signal only asks for a stop: loading and meshing go on to the first safe point,
  // where the checkpoint records what there is (a batch job's stop at any stage requeues).
  safePoints_.emplace(comm_, !request_.checkpoint.empty() && !request_.meshOnly,
                      request_.checkpointEvery, request_.stopAfter, startedAt_);
  load();
  stallForTests("load");
  mesh();
  stallForTests("mesh");
  if (request_.meshOnly) return reportMeshOnly();
  plan();
  replayRefinement();
  layOut();
  restart();
  prepareTracing();
  // Rounds of form factors and solve: one, or with --target-error or --refine-rounds as many as
  // it takes, each adding samples to the same rows (the sequence is extensible) or splitting
  // patches (the rows sampled afresh), and starting from the last B.
  do {
    sample();
    chooseSolver();
    repair();
    solve();
  } while (nextRound());
  write();
  return exit_code::kOk;
}

// 5. Write the result, each rank its own slab. The finished run's state goes first, and into
// place at once: a later --restart with more --rays adds to these rows, a run whose last
// checkpoint could not be written (a full disk) fails without leaving a result that looks
// complete, and whatever then stops the result (a full disk, a rank that dies) leaves the
// finished solve for --restart to write without solving again.
void SolvePipeline::write() {
  if (!request_.checkpoint.empty()) {
    // B lent to the checkpoint, not copied (this is the run's memory peak), and given back.
    state_.progress =
        SolveProgress{{2, 2, 2}, std::move(solved_.solution.radiosity), solved_.report.history};
    struct GiveBack {
      std::vector<Rgb>& to;
      std::vector<Rgb>& from;
      ~GiveBack() { to = std::move(from); }
    } giveBack{solved_.solution.radiosity, state_.progress.radiosity};
    writeCheckpoint("done");
  }
  CollectiveOutputs outputs(comm_);
  attributes_.ranks = console_.ranks();
  attributes_.solverChoice = solved_.solverChoice;
  attributes_.software = softwareVersions();
  recordSolve(attributes_, solved_.report, solved_.calibration);
  attributes_.solveFigures["refinement_rounds"] = state_.refinement.rounds();
  recordOptionsUsed();
  attributes_.options = describeSettings(request_, plan_, mesh_.maxArea, console_.ranks());
  {
    solve::ScopedStage stage("Write result");
    // F goes to the file as it is, each rank its own rows.
    FormFactorOutput formFactors;
    formFactors.rowSumHistogram = formFactors_.rowSumHistogram;
    formFactors.rowSumBinEdges = formfactor::rowSumBinEdges();
    if (request_.saveFormFactors && formFactors_.storeHandedBack) {
      formFactors.store = &state_.rows.values;  // F's one store, as the solve gave it back
    } else if (request_.saveFormFactors) {
      formFactors.rows = &formFactors_.repaired;
    }
    mesh_.patches.vertices = mesh_.worldVertices;
    if (!request_.thermal.empty()) recordHeat();  // (areas in the user's units)
    if (!formFactors_.groups.empty())
      formFactors_.groups.area = formfactor::groupAreas(mesh_.patches);  // (and here)
    formFactors.groups = formFactors_.groups;
    solved_.solution.hidden.assign(mesh_.hidden.begin() + mesh_.owned.begin,
                                   mesh_.hidden.begin() + mesh_.owned.end);
    // Left out of the solve: nothing reaches a hidden patch (B = E already, as ρ = 0 there).
    for (size_t i = 0; i < solved_.solution.hidden.size(); ++i)
      if (solved_.solution.hidden[i]) solved_.solution.irradiance[i] = Rgb{0, 0, 0};
    try {
      stageResult(outputs, request_.output, mesh_.patches, solved_.solution, attributes_,
                  formFactors);
    } catch (const Error& e) {
      if (request_.checkpoint.empty()) throw;
      // The finished solve is not lost with the result: the checkpoint is in place already.
      throw Error(e.exitCode(), std::string(e.what()) + "; the checkpoint " + request_.checkpoint +
                                    " holds the finished solve: run again with --restart " +
                                    request_.checkpoint + " to write the result");
    }
    outputs.commit();
    endStage("write");
  }
  if (!request_.thermal.empty()) printHeat();
  std::ostringstream times;
  times << "wrote " << request_.output << "; stage times (s):";
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
  if (console_.isJson())
    console_.json(solveJson({request_.output, mesh_.patches.triangleCount(), &attributes_,
                             peakMegabytes_, request_.thermal.empty() ? nullptr : &thermal_.heat}));
}

void SolvePipeline::recordOptionsUsed() {
  recordOptions({request_, plan_, mesh_.maxArea, mesh_.lengthUnit, solved_.report.solver},
                attributes_);
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
  radiosity::writeCheckpoint(comm_, request_.checkpoint, state_);
  reportCheckpoint(console_, request_.checkpoint, stage, state_.rows.rowSamples,
                   slowestRank(comm_, MPI_Wtime() - start));
}

Error SolvePipeline::stopped() const {
  return Error(exit_code::kStoppedBySignal, "stopped by " + safePoints_->stopReason() +
                                                "; the run's state is in " + request_.checkpoint +
                                                ": resume with --restart " + request_.checkpoint);
}

solve::VarianceScale SolvePipeline::calibrate(const std::vector<Rgb>& radiosity) {
  solve::ScopedStage stage("Error calibration");  // (inside the solve's stage)
  console_.info("  solve: calibrating the sampling error's model against re-gathered rows");
  solved_.calibration = solve::calibrateSamplingError(comm_, *tracer_, mesh_.patches, mesh_.owned,
                                                      samplingOptions(request_, plan_), radiosity);
  return solved_.calibration.scale;
}

void SolvePipeline::estimateDiscretisation(const std::vector<Rgb>& irradiance,
                                           std::vector<Rgb>& error, std::vector<Rgb>& variance) {
  solve::ScopedStage stage("Discretisation rays");  // (inside the solve's stage)
  const int64_t rays = solve::discretisationRays(plan_.rays);
  console_.info("  solve: estimating the discretisation error: " + std::to_string(rays) +
                " rays from each patch");
  // (timed from the gathering rays' first row: the slopes before them are another pace)
  std::optional<ProgressReporter> progress;
  std::function<void(int64_t)> callback;
  if (!console_.isQuiet())
    callback = [&](int64_t done) {
      if (!progress)
        progress.emplace(console_, mesh_.owned.size(), rays, "rays", "discretisation estimate");
      (*progress)(done);
    };
  // (H with the surroundings' share: the estimate rebuilds each patch's J as E + ρH)
  std::vector<Rgb> withSurroundings;
  if (!thermal_.surroundingsIrradiance.empty()) {
    withSurroundings = irradiance;
    addSurroundingsIrradiance(withSurroundings);
  }
  solve::DiscretisationEstimate estimate = solve::estimateDiscretisationError(
      comm_,
      {*tracer_, mesh_.patches, mesh_.owned, request_.seed, rays, request_.threads,
       withSurroundings.empty() ? irradiance : withSurroundings, mesh_.hidden, mayRefineNext()},
      callback);
  error = std::move(estimate.error);
  variance = std::move(estimate.variance);
  solved_.discretisation = std::move(estimate.report);
}

// A checkpoint from inside the form-factor stage: the rows so far, and those of an earlier
// checkpoint not reached yet, lent for the write and given back (also when it fails).
void SolvePipeline::saveRows(SampledRows& rows) {
  state_.rows = std::move(rows);
  struct GiveBack {
    SampledRows& to;
    SampledRows& from;
    ~GiveBack() { to = std::move(from), from = SampledRows(); }
  } giveBack{rows, state_.rows};
  writeCheckpoint("formfactors");
}

// A periodic or final checkpoint from inside the solve: the rows of F (`rows`, F's one store,
// which PETSc goes on using, lent for the write; or the copy kept here) and the solve's progress.
void SolvePipeline::saveProgress(const SolveProgress& progress, formfactor::SplitRows* rows) {
  state_.progress = progress;
  if (rows) state_.rows.values = std::move(*rows);
  try {
    writeCheckpoint("solve");
  } catch (...) {
    if (rows) *rows = std::move(state_.rows.values);
    throw;
  }
  if (rows) *rows = std::move(state_.rows.values);
  safePoints_->checkpointWritten();
}

}  // namespace radiosity::run
