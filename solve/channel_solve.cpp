// One channel's solve: the solver named in the options, restarted after every safe point that
// saves, then its final residual, error bound and condition estimate.
#include "solve/channel_solve.h"

#include <cmath>
#include <limits>

#include "core/channels.h"
#include "solve/assemble.h"
#include "solve/shared_system.h"

namespace radiosity::solve {

int64_t iterationsRecorded(const SolveHistory& history, int c) {
  int64_t last = 0;
  for (size_t k = 0; k < history.size(); ++k)
    if (history.channel[k] == c) last = history.iteration[k] + 1;
  return last;
}

namespace {

PetscErrorCode saveProgress(const ChannelSystem& system, Vec E, Vec B, int c,
                            const Options& options, const LocalSolution& solution,
                            const Report& report, RunState& run) {
  PetscFunctionBeginUser;
  PetscCall(scatterSolution(system, E, B));
  SolveProgress progress;
  progress.channelState = run.channelState;
  progress.channelState[c] = 1;
  progress.radiosity = solution.radiosity;
  PetscCall(readChannel(B, progress.radiosity, c));
  progress.history = report.history;
  PetscCall(handOver(progress, options, run));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode handOver(const SolveProgress& progress, const Options& options, RunState& run) {
  PetscFunctionBeginUser;
  formfactor::SampleTally rows;  // F as sampled, for the checkpoint; freed once written
  if (options.rebuildTally) PetscCall(tallyFromMatrix(run.formFactors, run.samples, &rows));
  try {
    options.save(progress, options.rebuildTally ? &rows : nullptr);
  } catch (...) {
    run.saveFailure = std::current_exception();
    run.stopped = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode solveOneChannel(Mat M, Vec rho, Vec weight, Vec E, Vec area, Vec B, Vec start, int c,
                               double rtol, const Options& options, double startTime,
                               WorkCount& work, const LocalSolution& solution, Report& report,
                               RunState& run, ChannelFailure& failure, ChannelResult& result,
                               const BlockOutcome* block) {
  ChannelSystem system;
  ChannelOutcome outcome;
  Vec r = nullptr;
  PetscReal residualNorm, bound, solutionNorm;
  PetscFunctionBeginUser;
  PetscCall(buildChannelSystem(M, rho, weight, E, area, work, &system));
  if (start) {  // go on from an iterate
    if (system.reflective) {
      PetscCall(VecISCopy(start, system.reflective, SCATTER_REVERSE, system.solution));
    } else {
      PetscCall(VecCopy(start, system.solution));
    }
  }
  HistoryRecorder recorder;
  recorder.history = &report.history;
  recorder.channel = c;
  recorder.start = startTime;
  recorder.normalise = system.emissionNorm;
  recorder.firstIteration = iterationsRecorded(report.history, c);
  recorder.progress = &options.progress;
  int64_t iterations = 0;
  bool solved = false;
  if (block) {  // the block's iterate: taken if it meets rtol here (it should)
    PetscCall(VecDuplicate(system.rhs, &r));
    PetscCall(channelResidual(system, system.solution, r, work));
    PetscCall(VecNorm(r, NORM_2, &residualNorm));
    solved = residualNorm <= rtol * system.emissionNorm;
    if (solved) {
      outcome.converged = true;
      outcome.conditionEstimate = block->conditionEstimate;
      outcome.conditionSource = block->conditionSource + " (the channels together)";
    } else {
      PetscCall(VecDestroy(&r));
    }
  }
  while (!solved) {
    outcome = ChannelOutcome();
    if (options.solver == Solver::kSouthwell) {
      PetscCall(solveBySouthwell(system, rtol, recorder, options.safePoint, work, outcome));
    } else {
      PetscCall(
          solveWithKsp(system, options.solver, rtol, recorder, options.safePoint, work, outcome));
    }
    iterations += outcome.iterations;
    recorder.firstIteration += outcome.iterations;
    if (outcome.interrupted == SafePointAction::kContinue) break;
    PetscCall(saveProgress(system, E, B, c, options, solution, report, run));
    if (outcome.interrupted == SafePointAction::kStop) run.stopped = true;
    if (run.stopped) break;
  }
  result.iterations += iterations;
  if (run.stopped) {
    PetscCall(destroyChannelSystem(&system));
    PetscFunctionReturn(0);
  }
  // The final residual of the unscaled system, and from it the error bound.
  if (!r) {
    PetscCall(VecDuplicate(system.rhs, &r));
    PetscCall(channelResidual(system, system.solution, r, work));
    PetscCall(VecNorm(r, NORM_2, &residualNorm));
  }
  PetscCall(relativeErrorBound(system, r, system.solution, &bound));
  PetscCall(VecNorm(system.solution, NORM_INFINITY, &solutionNorm));
  const double relative =
      system.emissionNorm > 0 ? residualNorm / system.emissionNorm : residualNorm;
  result.solved = true;
  result.relativeResidual = relative;
  result.errorBound = bound;
  result.absoluteBound = solutionNorm > 0 ? bound * solutionNorm : bound;
  result.unknowns = system.unknowns;
  result.contraction = system.contraction;
  result.condition = outcome.conditionEstimate;
  result.conditionSource = outcome.conditionSource;
  if (result.condition <= 0) {
    result.condition = system.contraction < 1 ? (1 + system.contraction) / (1 - system.contraction)
                                              : std::numeric_limits<double>::infinity();
    result.conditionSource = "bound (1 + q)/(1 - q) of the Jacobi-scaled operator";
  }
  if (!std::isfinite(relative)) {
    failure.message = std::string("the ") + kChannelNames[c] +
                      " channel's iterate is not finite (NaN or Inf): nothing was written";
  } else if (!outcome.converged) {
    failure.message = std::string("the ") + kChannelNames[c] + " channel " + outcome.failure;
  }
  PetscCall(scatterSolution(system, E, B));
  PetscCall(VecDestroy(&r));
  PetscCall(destroyChannelSystem(&system));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
