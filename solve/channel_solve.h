// Private to solve/: one colour channel solved by the chosen solver, through its safe points
// (saving progress when asked), and how it ended.
#pragma once

#include <petscmat.h>

#include <array>
#include <cstdint>
#include <exception>
#include <string>

#include "solve/channel_system.h"
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

/// Solves channel c to `rtol`, from `start` (a full-length B) or from b. Leaves B in `B`.
PetscErrorCode solveOneChannel(Mat M, Vec rho, Vec weight, Vec E, Vec area, Vec B, Vec start, int c,
                               double rtol, const Options& options, double startTime,
                               WorkCount& work, const LocalSolution& solution, Report& report,
                               RunState& run, ChannelFailure& failure, ChannelResult& result);

}  // namespace radiosity::solve
