// Private to solve/: one colour channel solved by the chosen solver, through its safe points
// (saving progress when asked), and how it ended.
#pragma once

#include <petscmat.h>

#include <array>
#include <cstdint>
#include <exception>
#include <string>

#include "solve/channel_system.h"
#include "solve/petsc_handles.h"
#include "solve/shared_system.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

struct ChannelFailure {
  std::string message;  ///< empty when every channel converged
};

/// What the channels share while they are solved one after another: the progress a safe point
/// saves, and how the run ended.
struct RunState {
  std::array<int, 3> channelState{};
  bool stopped = false;            ///< a safe point said kStop (after saving)
  std::exception_ptr saveFailure;  ///< save() threw: rethrown once PETSc objects are freed
  /// With Options::handBackRows: F's one store, which M is made on, for a save. Not owned: the
  /// SharedSystem's.
  formfactor::SplitRows* formFactors = nullptr;
};

/// One channel's solve, as it ended.
struct ChannelResult {
  bool solved = false;  ///< by an iteration in this run (not left out, copied or resumed done)
  int64_t iterations = 0;
  double relativeResidual = 0;
  double errorBound = 0;     ///< ‖B* − B‖∞ / ‖B‖∞ bound
  double absoluteBound = 0;  ///< ‖B* − B‖∞ bound
  int64_t unknowns = 0;
  double contraction = 0;
  double condition = 0;
  std::string conditionSource;
};

/// How the channels solved together (solveChannelBlock) ended.
struct BlockOutcome {
  int64_t iterations = 0;
  bool converged = false;  ///< every channel's relative residual ≤ rtol
  double conditionEstimate = 0;
  std::string conditionSource;
};

/// What every channel's solve works with: the stored system (s.rho, s.E filled with the channel
/// by the caller; s.B receives its B), the scene's rows, the options, and the records the
/// channels add to one after another: the work counted, the history, the safe points' state.
struct ChannelContext {
  const SharedSystem& shared;
  const std::vector<Rgb>& reflectance;
  const std::vector<Rgb>& emission;
  const Options& options;
  double startTime = 0;           ///< MPI_Wtime() at the start of the solve
  const LocalSolution& solution;  ///< the channels solved so far, for a save
  WorkCount& work;
  SolveHistory& history;
  RunState& run;
};

/// One channel to solve.
struct ChannelTask {
  int channel = 0;
  double rtol = 0;
  Vec start = nullptr;  ///< a full-length B to go on from; null: from b
  /// `start` is that block's iterate; if it meets rtol in this channel it is taken after one
  /// product, without iterating.
  const BlockOutcome* block = nullptr;
};

/// How one call of solveOneChannel ended.
struct ChannelEnd {
  int64_t iterations = 0;  ///< iterations this call did
  bool finished = false;   ///< false: a safe point stopped the run first (run.stopped)
  ChannelResult result;    ///< with `finished`: the channel's figures (iterations: 0)
  std::string failure;     ///< with `finished`: why the channel failed; empty when it converged
};

/// Solves the task's channel, leaving its B in context.shared.B.
PetscErrorCode solveOneChannel(const ChannelContext& context, const ChannelTask& task,
                               ChannelEnd* end);

/// The iterations of `end` added to `result`, and its figures and failure taken where it
/// finished.
void takeChannelEnd(const ChannelEnd& end, ChannelResult& result, ChannelFailure& failure);

/// Whether `solver` solves `channels` channels together, F having `nonzerosPerRow`: jacobi
/// always, gmres where its k-times longer Krylov vectors cost no more memory than F; never for
/// the others. PETSc option -solve_channels_together true/false decides instead.
PetscErrorCode solvesChannelsTogether(Solver solver, int channels, double nonzerosPerRow,
                                      bool* together);

/// Solves `channels` (two or three, each with E ≠ 0) together to `rtol`, one pass over F per
/// iteration for all (solve/channel_block.cpp), from iterate[c] where not null; saves progress at
/// safe points as every channel of the block in progress. Leaves each channel's B (full length)
/// in iterate[c] (created where null) for solveOneChannel to finish from.
PetscErrorCode solveChannelBlock(const ChannelContext& context, const std::vector<int>& channels,
                                 double rtol, std::array<OwnedVec, 3>& iterate,
                                 BlockOutcome* block);

/// Hands a safe point's progress to options.save with this rank's rows of F (run.formFactors
/// with Options::handBackRows); a save that throws stops the run (rethrown by
/// solveRadiosity once PETSc's objects are freed).
PetscErrorCode handOver(const SolveProgress& progress, const Options& options, RunState& run);

/// The iterations recorded for channel c so far (a resumed channel goes on counting from them).
int64_t iterationsRecorded(const SolveHistory& history, int c);

}  // namespace radiosity::solve
