// One channel's solve: the solver named in the options, restarted after every safe point that
// saves, then its final residual, error bound and condition estimate.
#include "solve/channel_solve.h"

#include <cmath>
#include <limits>

#include "core/channels.h"
#include "solve/shared_system.h"

namespace radiosity::solve {

int64_t iterationsRecorded(const SolveHistory& history, int c) {
  int64_t last = 0;
  for (size_t k = 0; k < history.size(); ++k)
    if (history.channel[k] == c) last = history.iteration[k] + 1;
  return last;
}

namespace {

PetscErrorCode saveProgress(const ChannelContext& context, const ChannelSystem& system, int c) {
  const SharedSystem& s = context.shared;
  PetscFunctionBeginUser;
  PetscCall(scatterSolution(system, s.E, s.B));
  SolveProgress progress;
  progress.channelState = context.run.channelState;
  progress.channelState[c] = 1;
  progress.radiosity = context.solution.radiosity;
  PetscCall(readChannel(s.B, progress.radiosity, c));
  progress.history = context.history;
  PetscCall(handOver(progress, context.options, context.run));
  PetscFunctionReturn(0);
}

// The iterate of the block the channel was solved in, if it meets rtol here (it should): then
// the channel is converged without iterating, *residualNorm its residual in r.
PetscErrorCode takeBlockIterate(const ChannelContext& context, const ChannelTask& task,
                                const ChannelSystem& system, OwnedVec& r, PetscReal* residualNorm,
                                ChannelOutcome* outcome, bool* taken) {
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(system.rhs, r.out()));
  PetscCall(channelResidual(system, system.solution, r, context.work));
  PetscCall(VecNorm(r, NORM_2, residualNorm));
  *taken = *residualNorm <= task.rtol * system.emissionNorm;
  if (*taken) {
    outcome->converged = true;
    outcome->conditionEstimate = task.block->conditionEstimate;
    outcome->conditionSource = task.block->conditionSource + " (the channels together)";
  } else {
    r.reset();
  }
  PetscFunctionReturn(0);
}

// The chosen solver, restarted after every safe point that saves, until it ends or the run
// stops; *iterations counts them all.
PetscErrorCode iterate(const ChannelContext& context, const ChannelTask& task,
                       ChannelSystem& system, ChannelOutcome* outcome, int64_t* iterations) {
  const Options& options = context.options;
  HistoryRecorder recorder;
  recorder.history = &context.history;
  recorder.channel = task.channel;
  recorder.start = context.startTime;
  recorder.normalise = system.emissionNorm;
  recorder.firstIteration = iterationsRecorded(context.history, task.channel);
  recorder.progress = &options.progress;
  recorder.channelCount = options.channels;
  PetscFunctionBeginUser;
  while (true) {
    *outcome = ChannelOutcome();
    if (options.solver == Solver::kSouthwell) {
      PetscCall(
          solveBySouthwell(system, task.rtol, recorder, options.safePoint, context.work, *outcome));
    } else {
      PetscCall(solveWithKsp(system, options.solver, task.rtol, recorder, options.safePoint,
                             context.work, *outcome));
    }
    *iterations += outcome->iterations;
    recorder.firstIteration += outcome->iterations;
    if (outcome->interrupted == SafePointAction::kContinue) break;
    PetscCall(saveProgress(context, system, task.channel));
    if (outcome->interrupted == SafePointAction::kStop) context.run.stopped = true;
    if (context.run.stopped) break;
  }
  PetscFunctionReturn(0);
}

// The channel's figures from its final residual r (norm residualNorm) and the solver's outcome.
PetscErrorCode channelFigures(const ChannelSystem& system, Vec r, PetscReal residualNorm,
                              const ChannelOutcome& outcome, int c, int channels, ChannelEnd* end) {
  PetscReal bound, solutionNorm;
  PetscFunctionBeginUser;
  PetscCall(relativeErrorBound(system, r, system.solution, &bound));
  PetscCall(normOnR(system, system.solution, NORM_INFINITY, &solutionNorm));
  const double relative =
      system.emissionNorm > 0 ? residualNorm / system.emissionNorm : residualNorm;
  ChannelResult& result = end->result;
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
    end->failure = std::string("the ") + channelName(c, channels) +
                   " channel's iterate is not finite (NaN or Inf): nothing was written";
  } else if (!outcome.converged) {
    end->failure = std::string("the ") + channelName(c, channels) + " channel " + outcome.failure;
  }
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode handOver(const SolveProgress& progress, const Options& options, RunState& run) {
  PetscFunctionBeginUser;
  try {
    options.save(progress, options.handBackRows ? run.formFactors : nullptr);
  } catch (...) {
    run.saveFailure = std::current_exception();
    run.stopped = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode solveOneChannel(const ChannelContext& context, const ChannelTask& task,
                               ChannelEnd* end) {
  const SharedSystem& s = context.shared;
  ChannelSystem system;
  ChannelOutcome outcome;
  OwnedVec r;
  PetscReal residualNorm;
  PetscFunctionBeginUser;
  *end = ChannelEnd();
  PetscCall(buildChannelSystem(s.M, {s.rho, s.weight, s.E, s.area},
                               !needsExplicitMatrix(context.options.solver), context.work,
                               &system));
  if (task.start) {  // go on from an iterate
    if (system.reflective) {
      PetscCall(VecISCopy(task.start, system.reflective, SCATTER_REVERSE, system.solution));
    } else {
      PetscCall(VecCopy(task.start, system.solution));
      PetscCall(keepBlackRowsAtEmission(system));
    }
  }
  bool solved = false;
  if (task.block)
    PetscCall(takeBlockIterate(context, task, system, r, &residualNorm, &outcome, &solved));
  if (!solved) PetscCall(iterate(context, task, system, &outcome, &end->iterations));
  if (context.run.stopped) PetscFunctionReturn(0);
  // The final residual of the unscaled system, and from it the error bound.
  if (!r) {
    PetscCall(VecDuplicate(system.rhs, r.out()));
    PetscCall(channelResidual(system, system.solution, r, context.work));
    PetscCall(VecNorm(r, NORM_2, &residualNorm));
  }
  PetscCall(channelFigures(system, r, residualNorm, outcome, task.channel, context.options.channels,
                           end));
  end->finished = true;
  PetscCall(scatterSolution(system, s.E, s.B));
  PetscFunctionReturn(0);
}

void takeChannelEnd(const ChannelEnd& end, ChannelResult& result, ChannelFailure& failure) {
  const int64_t iterations = result.iterations + end.iterations;
  if (end.finished) {
    result = end.result;
    if (!end.failure.empty()) failure.message = end.failure;
  }
  result.iterations = iterations;
}

}  // namespace radiosity::solve
