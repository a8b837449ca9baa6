// Private to solve/: one colour channel solved by the chosen solver, through its safe points
// (saving progress when asked), and how it ended.
#pragma once

#include <petscmat.h>

#include <array>
#include <cstdint>
#include <exception>
#include <string>

#include "solve/channel_system.h"
#include "solve/shared_system.h"
#include "solve/solve.h"

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
  /// With Options::rebuildTally: the shared matrix M = F and the samples behind its rows, to
  /// rebuild the tally from at a save.
  Mat formFactors = nullptr;
  int64_t samples = 0;
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

/// Solves channel c to `rtol`, from `start` (a full-length B) or from b. Leaves B in `B`.
/// `block`: `start` is that block's iterate; if it meets rtol in this channel it is taken after
/// one product, without iterating.
PetscErrorCode solveOneChannel(Mat M, Vec rho, Vec weight, Vec E, Vec area, Vec B, Vec start, int c,
                               double rtol, const Options& options, double startTime,
                               WorkCount& work, const LocalSolution& solution, Report& report,
                               RunState& run, ChannelFailure& failure, ChannelResult& result,
                               const BlockOutcome* block = nullptr);

/// Whether `solver` solves `channels` channels together, F having `nonzerosPerRow`: jacobi
/// always, gmres where its k-times longer Krylov vectors cost no more memory than F; never for
/// the others. PETSc option -solve_channels_together true/false decides instead.
PetscErrorCode solvesChannelsTogether(Solver solver, int channels, double nonzerosPerRow,
                                      bool* together);

/// Solves `channels` (two or three, each with E ≠ 0) together, one pass over F per iteration for
/// all (solve/channel_block.cpp), from iterate[c] where not null; saves progress at safe points
/// as every channel of the block in progress. Leaves each channel's B (full length) in iterate[c]
/// (created where null; the caller destroys them) for solveOneChannel to finish from.
PetscErrorCode solveChannelBlock(const SharedSystem& s, const std::vector<int>& channels,
                                 const std::vector<Rgb>& reflectance,
                                 const std::vector<Rgb>& emission, std::array<Vec, 3>& iterate,
                                 double rtol, const Options& options, double startTime,
                                 WorkCount& work, const LocalSolution& solution, Report& report,
                                 RunState& run, BlockOutcome& block);

/// Hands a safe point's progress to options.save with this rank's rows of F (rebuilt from
/// run.formFactors with Options::rebuildTally); a save that throws stops the run (rethrown by
/// solveRadiosity once PETSc's objects are freed).
PetscErrorCode handOver(const SolveProgress& progress, const Options& options, RunState& run);

/// The iterations recorded for channel c so far (a resumed channel goes on counting from them).
int64_t iterationsRecorded(const SolveHistory& history, int c);

}  // namespace radiosity::solve
