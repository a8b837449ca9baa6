// Several colour channels solved as one system, so that each iteration reads F once for all of
// them instead of once per channel (an RGB scene's solve streams F a third as often). The
// channels' unknowns are interleaved patch by patch and F acts on them as PETSc's MAIJ matrix
// F ⊗ I_k, which shares M's storage; channel c is scaled by 1/‖E_c‖, so that the block's
// residual norm bounds each channel's relative residual and one KSP tolerance serves them all.
// Only for the solvers that iterate on the shell operator and need no entries of the matrix
// (gmres, jacobi). The per-channel solves then start from the block's iterates: each checks its
// own residual (one product) and takes the iterate if it meets rtol, so everything after the
// iteration (error bounds, black patches outside the iteration) is as for a channel alone.
#include <cmath>

#include "core/channels.h"
#include "solve/assemble.h"
#include "solve/channel_solve.h"
#include "solve/shared_system.h"
#include "solve/single_precision_matrix.h"

namespace radiosity::solve {

namespace {

// Component j of the interleaved `block` from the full-length `v` times `factor`, or back.
PetscErrorCode toComponent(Vec v, double factor, Vec block, PetscInt j, Vec work) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(v, work));
  PetscCall(VecScale(work, factor));
  PetscCall(VecStrideScatter(work, j, block, INSERT_VALUES));
  PetscFunctionReturn(0);
}
PetscErrorCode fromComponent(Vec block, PetscInt j, double factor, Vec v) {
  PetscFunctionBeginUser;
  PetscCall(VecStrideGather(block, j, v, INSERT_VALUES));
  PetscCall(VecScale(v, factor));
  PetscFunctionReturn(0);
}

// The block system of `channels` over every patch (a patch black in one channel has s = 0
// there: its equation is x = E), starting from `start[c]` (full-length B, or null: from b).
PetscErrorCode buildBlockSystem(const ChannelContext& context, const std::vector<int>& channels,
                                const std::array<OwnedVec, 3>& start,
                                const std::array<double, 3>& emissionNorm, ChannelSystem* system) {
  const SharedSystem& s = context.shared;
  const auto k = static_cast<PetscInt>(channels.size());
  OwnedVec v;
  PetscFunctionBeginUser;
  if (isSinglePrecisionMatrix(s.M)) {
    PetscCall(createSinglePrecisionComponents(s.M, k, system->matrix.out()));
  } else {
    PetscCall(MatCreateMAIJ(s.M, k, system->matrix.out()));  // shares M's values and indices
  }
  PetscCall(MatCreateVecs(system->matrix, system->rhs.out(), system->scale.out()));
  PetscCall(VecSetBlockSize(system->rhs, k));
  PetscCall(VecSetBlockSize(system->scale, k));
  PetscCall(VecDuplicate(system->rhs, system->solution.out()));
  PetscCall(VecDuplicate(s.E, v.out()));
  for (PetscInt j = 0; j < k; ++j) {
    const int c = channels[j];
    PetscCall(fillChannel(v, context.reflectance, c));
    PetscCall(VecPointwiseDivide(v, v, s.weight));  // s = ρ / w
    PetscCall(VecStrideScatter(v, j, system->scale, INSERT_VALUES));
    PetscCall(fillChannel(v, context.emission, c));
    PetscCall(toComponent(v, 1 / emissionNorm[c], system->rhs, j, v));  // v is E_c / ‖E_c‖ now
    if (start[c]) {
      PetscCall(toComponent(start[c], 1 / emissionNorm[c], system->solution, j, v));
    } else {
      PetscCall(VecStrideScatter(v, j, system->solution, INSERT_VALUES));  // from b
    }
  }
  v.reset();
  PetscInt patches;
  MatInfo info;
  PetscCall(MatGetSize(s.M, &patches, nullptr));
  PetscCall(MatGetInfo(s.M, MAT_GLOBAL_SUM, &info));
  system->unknowns = k * patches;
  // Entries multiplied per product: each of M's for every channel (M is read once).
  system->nonzeros = k * static_cast<PetscInt>(info.nz_used);
  system->emissionNorm = 1;  // the channels are scaled: rtol applies to the residual itself
  PetscCall(contractionAndDiagonal(s.M, k, *system));
  PetscFunctionReturn(0);
}

// The block's iterate as a checkpoint sees it: every channel of the block in progress.
PetscErrorCode saveBlockProgress(const ChannelContext& context, const ChannelSystem& system,
                                 const std::vector<int>& channels,
                                 const std::array<double, 3>& emissionNorm, Vec v) {
  PetscFunctionBeginUser;
  SolveProgress progress;
  progress.channelState = context.run.channelState;
  progress.radiosity = context.solution.radiosity;
  for (size_t j = 0; j < channels.size(); ++j) {
    const int c = channels[j];
    progress.channelState[c] = 1;
    PetscCall(fromComponent(system.solution, static_cast<PetscInt>(j), emissionNorm[c], v));
    PetscCall(readChannel(v, progress.radiosity, c));
  }
  progress.history = context.history;
  PetscCall(handOver(progress, context.options, context.run));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode solvesChannelsTogether(Solver solver, int channels, double nonzerosPerRow,
                                      bool* together) {
  PetscBool asked = PETSC_TRUE, set = PETSC_FALSE;
  PetscFunctionBeginUser;
  // (read whatever the solver, so that a bad value is refused, not ignored)
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-solve_channels_together", &asked, &set));
  PetscInt restart = 30;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-ksp_gmres_restart", &restart, nullptr));
  *together = false;
  if (solver != Solver::kGmres && solver != Solver::kJacobi) PetscFunctionReturn(0);
  if (set) {
    *together = asked;
    PetscFunctionReturn(0);
  }
  // GMRES keeps up to restart + 2 Krylov vectors, k times longer for k channels together: worth
  // it where they cost no more than F itself (8 B (restart + 2) k per row against 12 B per
  // nonzero), which is also where F's rows are long enough for its reads to dominate an
  // iteration (the measured gains and memory cost are in the docs).
  *together = solver == Solver::kJacobi  // (no Krylov basis)
              || 8.0 * (restart + 2) * channels <= 12.0 * nonzerosPerRow;
  PetscFunctionReturn(0);
}

PetscErrorCode solveChannelBlock(const ChannelContext& context, const std::vector<int>& channels,
                                 double rtol, std::array<OwnedVec, 3>& iterate,
                                 BlockOutcome* block) {
  const Options& options = context.options;
  ChannelSystem system;
  std::array<double, 3> emissionNorm{1, 1, 1};
  OwnedVec v;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(context.shared.E, v.out()));
  for (int c : channels) {
    PetscCall(fillChannel(v, context.emission, c));
    PetscCall(VecNorm(v, NORM_2, &emissionNorm[c]));
  }
  PetscCall(buildBlockSystem(context, channels, iterate, emissionNorm, &system));
  HistoryRecorder recorder;
  recorder.history = &context.history;
  recorder.channel = channels.front();
  recorder.start = context.startTime;
  recorder.together = channels;
  recorder.progress = &options.progress;
  recorder.channelCount = options.channels;
  for (int c : channels)
    recorder.firstIteration =
        std::max(recorder.firstIteration, iterationsRecorded(context.history, c));
  ChannelOutcome outcome;
  while (true) {
    outcome = ChannelOutcome();
    PetscCall(solveWithKsp(system, options.solver, rtol, recorder, options.safePoint, context.work,
                           outcome));
    block->iterations += outcome.iterations;
    recorder.firstIteration += outcome.iterations;
    if (outcome.interrupted == SafePointAction::kContinue) break;
    PetscCall(saveBlockProgress(context, system, channels, emissionNorm, v));
    if (outcome.interrupted == SafePointAction::kStop) context.run.stopped = true;
    if (context.run.stopped) break;
  }
  block->converged = outcome.converged && !context.run.stopped;
  block->conditionEstimate = outcome.conditionEstimate;
  block->conditionSource = outcome.conditionSource;
  // Each channel's B, full length, where the channel solves take it from.
  for (size_t j = 0; j < channels.size(); ++j) {
    const int c = channels[j];
    if (!iterate[c]) PetscCall(VecDuplicate(context.shared.E, iterate[c].out()));
    PetscCall(
        fromComponent(system.solution, static_cast<PetscInt>(j), emissionNorm[c], iterate[c]));
  }
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
