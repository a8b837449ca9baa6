// The PETSc adapter. M = diag(w) F is assembled once (MPIAIJ; w = 1, or the patch areas for
// CG's symmetric form) and every channel iterates on it through a ChannelSystem: a shell
// operator, or M turned in place into the explicit form and back; never a copy per channel.
// PETSc-style functions below return PetscErrorCode; the C++ entry point turns failures into
// exceptions after cleaning up.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <string>

#include "solve/assemble.h"
#include "solve/channel_plan.h"
#include "solve/channel_system.h"
#include "solve/sampling_error.h"
#include "solve/solve.h"

namespace radiosity::solve {

namespace {

constexpr const char* kChannelName[3] = {"red", "green", "blue"};

void check(PetscErrorCode code, const char* what) {
  if (code) {
    throw Error(exit_code::kFailure,
                std::string("PETSc failed in ") + what + " (error " + std::to_string(code) + ")");
  }
}

// Copies channel c of per-row triples into a PETSc vector.
PetscErrorCode fillChannel(Vec v, const std::vector<Rgb>& values, int c) {
  PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &array));
  for (size_t r = 0; r < values.size(); ++r) array[r] = values[r][c];
  PetscCall(VecRestoreArray(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode fillValues(Vec v, const std::vector<double>& values) {
  PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &array));
  std::copy(values.begin(), values.end(), array);
  PetscCall(VecRestoreArray(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode readChannel(Vec v, std::vector<Rgb>& values, int c) {
  const PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(v, &array));
  for (size_t r = 0; r < values.size(); ++r) values[r][c] = array[r];
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscFunctionReturn(0);
}

// H = F B = diag(1/w) M B: the flux arriving per unit area.
PetscErrorCode irradiance(Mat M, Vec weight, Vec B, Vec H) {
  PetscFunctionBeginUser;
  PetscCall(MatMult(M, B, H));
  PetscCall(VecPointwiseDivide(H, H, weight));
  PetscFunctionReturn(0);
}

struct ChannelFailure {
  std::string message;  ///< empty when every channel converged
};

// What the channels share while they are solved one after another: the progress a safe point
// saves, and how the run ended.
struct RunState {
  std::array<int, 3> channelState{};
  bool stopped = false;            ///< a safe point said kStop (after saving)
  std::exception_ptr saveFailure;  ///< save() threw: rethrown once PETSc objects are freed
};

// The last iteration recorded for channel c (a resumed channel goes on counting from it).
int64_t iterationsRecorded(const SolveHistory& history, int c) {
  int64_t last = 0;
  for (size_t k = 0; k < history.size(); ++k)
    if (history.channel[k] == c) last = history.iteration[k] + 1;
  return last;
}

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
  try {
    options.save(progress);
  } catch (...) {
    run.saveFailure = std::current_exception();
    run.stopped = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode solveOneChannel(Mat M, Vec rho, Vec weight, Vec E, Vec area, Vec B, int c,
                               const Options& options, double start, WorkCount& work,
                               const LocalSolution& solution, Report& report, RunState& run,
                               ChannelFailure& failure) {
  ChannelSystem system;
  ChannelOutcome outcome;
  Vec r;
  PetscReal residualNorm, bound;
  PetscFunctionBeginUser;
  PetscCall(buildChannelSystem(M, rho, weight, E, area, work, &system));
  if (options.resume && options.resume->channelState[c] == 1) {  // go on from the iterate
    PetscCall(fillChannel(B, options.resume->radiosity, c));
    if (system.reflective) {
      PetscCall(VecISCopy(B, system.reflective, SCATTER_REVERSE, system.solution));
    } else {
      PetscCall(VecCopy(B, system.solution));
    }
  }
  HistoryRecorder recorder{&report.history, c, start, system.emissionNorm,
                           iterationsRecorded(report.history, c)};
  int64_t iterations = 0;
  while (true) {
    outcome = ChannelOutcome();
    if (options.solver == "southwell") {
      PetscCall(solveBySouthwell(system, options.rtol, recorder, options.safePoint, work, outcome));
    } else {
      PetscCall(solveWithKsp(system, options.solver, options.rtol, recorder, options.safePoint,
                             work, outcome));
    }
    iterations += outcome.iterations;
    recorder.firstIteration += outcome.iterations;
    if (outcome.interrupted == SafePointAction::kContinue) break;
    PetscCall(saveProgress(system, E, B, c, options, solution, report, run));
    if (outcome.interrupted == SafePointAction::kStop) run.stopped = true;
    if (run.stopped) break;
  }
  if (run.stopped) {
    PetscCall(destroyChannelSystem(&system));
    PetscFunctionReturn(0);
  }
  // The final residual of the unscaled system, and from it the error bound.
  PetscCall(VecDuplicate(system.rhs, &r));
  PetscCall(channelResidual(system, system.solution, r, work));
  PetscCall(VecNorm(r, NORM_2, &residualNorm));
  PetscCall(relativeErrorBound(system, r, system.solution, &bound));
  const double relative =
      system.emissionNorm > 0 ? residualNorm / system.emissionNorm : residualNorm;
  report.iterations += iterations;
  report.residual = std::max(report.residual, relative);
  report.unknowns += system.unknowns;
  report.contraction = std::max<double>(report.contraction, system.contraction);
  report.errorBound = std::max<double>(report.errorBound, bound);
  ++report.channelsSolved;
  double condition = outcome.conditionEstimate;
  std::string source = outcome.conditionSource;
  if (condition <= 0) {
    condition = system.contraction < 1 ? (1 + system.contraction) / (1 - system.contraction)
                                       : std::numeric_limits<double>::infinity();
    source = "bound (1 + q)/(1 - q) of the Jacobi-scaled operator";
  }
  if (condition > report.conditionEstimate || report.conditionSource.empty()) {
    report.conditionEstimate = std::max(report.conditionEstimate, condition);
    report.conditionSource = source;
  }
  if (!std::isfinite(relative)) {
    failure.message = std::string("the ") + kChannelName[c] +
                      " channel's iterate is not finite (NaN or Inf): nothing was written";
  } else if (!outcome.converged) {
    failure.message = std::string("the ") + kChannelName[c] + " channel " + outcome.failure;
  }
  PetscCall(scatterSolution(system, E, B));
  PetscCall(VecDestroy(&r));
  PetscCall(destroyChannelSystem(&system));
  PetscFunctionReturn(0);
}

PetscErrorCode solveChannels(formfactor::SparseRows& rows, int64_t globalCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& localArea, const Options& options,
                             LocalSolution& solution, Report& report, RunState& run,
                             ChannelFailure& failure) {
  Mat M;
  Vec rho, E, B, H, weight, area;
  PetscFunctionBeginUser;
  // CG iterates on the symmetric form, so it stores S = diag(area) F; the others F itself.
  const bool symmetricForm = options.solver == "cg";
  PetscCall(assembleRows(PETSC_COMM_WORLD, rows, symmetricForm ? &localArea : nullptr, &M));
  PetscInt rowsInAll, columnsInAll;
  PetscCall(MatGetSize(M, &rowsInAll, &columnsInAll));
  PetscCheck(rowsInAll == globalCount, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
             "the ranks' rows add up to %" PetscInt_FMT " patches, not %" PetscInt_FMT, rowsInAll,
             static_cast<PetscInt>(globalCount));
  PetscCall(MatCreateVecs(M, &B, &E));
  PetscCall(VecDuplicate(E, &rho));
  PetscCall(VecDuplicate(E, &H));
  PetscCall(VecDuplicate(E, &weight));
  PetscCall(VecDuplicate(E, &area));
  PetscCall(fillValues(area, localArea));
  if (symmetricForm) {
    PetscCall(VecCopy(area, weight));
  } else {
    PetscCall(VecSet(weight, 1.0));
  }

  // Leave out what the scene does not need: channels without reflection (B = E), channels
  // equal to one already solved, and black patches inside a channel (ChannelSystem).
  const ChannelPlan plan = planChannels(PETSC_COMM_WORLD, rows, reflectance, emission);
  rows = formfactor::SparseRows();  // F lives in M from here on: stored once
  report.leftOut = plan.leftOut();
  report.solver = options.solver;
  if (options.resume) report.history = options.resume->history;
  WorkCount work;
  const double start = MPI_Wtime();
  for (int c = 0; c < 3 && failure.message.empty() && !run.stopped; ++c) {
    if (plan.singular[c]) {
      failure.message = std::string("the ") + kChannelName[c] +
                        " channel is singular: every patch of a closed scene reflects all the "
                        "light it gets (rho = 1), so I - F has no inverse; lower the reflectance";
      break;
    }
    if (plan.sameAs[c] >= 0) {
      for (size_t r = 0; r < solution.radiosity.size(); ++r) {
        solution.radiosity[r][c] = solution.radiosity[r][plan.sameAs[c]];
        solution.irradiance[r][c] = solution.irradiance[r][plan.sameAs[c]];
        if (!solution.radiosityStderr.empty())
          solution.radiosityStderr[r][c] = solution.radiosityStderr[r][plan.sameAs[c]];
      }
      run.channelState[c] = 2;
      continue;
    }
    PetscCall(fillChannel(E, emission, c));
    if (plan.noReflection[c]) {
      PetscCall(VecCopy(E, B));  // B = E; H = F E all the same
    } else if (options.resume && options.resume->channelState[c] == 2) {
      PetscCall(fillChannel(B, options.resume->radiosity, c));  // solved before the restart
    } else {
      PetscCall(fillChannel(rho, reflectance, c));
      PetscCall(solveOneChannel(M, rho, weight, E, area, B, c, options, start, work, solution,
                                report, run, failure));
      if (run.stopped) break;
    }
    PetscCall(readChannel(B, solution.radiosity, c));
    PetscCall(irradiance(M, weight, B, H));
    PetscCall(readChannel(H, solution.irradiance, c));
    if (options.samplesPerRow > 0 && !plan.noReflection[c]) {  // B = E has no sampling error
      Vec standardError;
      PetscReal relative;
      PetscCall(VecDuplicate(B, &standardError));
      PetscCall(fillChannel(rho, reflectance, c));
      PetscCall(samplingError(M, weight, rho, B, H, area, options.samplesPerRow, standardError,
                              &relative));
      PetscCall(readChannel(standardError, solution.radiosityStderr, c));
      report.relativeStderr = std::max<double>(report.relativeStderr, relative);
      PetscCall(VecDestroy(&standardError));
    }
    run.channelState[c] = 2;
  }
  report.converged = failure.message.empty();
  report.matrixProducts = work.matrixProducts;
  report.nonzeroProducts = work.nonzeroProducts;

  for (Vec* v : {&rho, &E, &B, &H, &weight, &area}) PetscCall(VecDestroy(v));
  PetscCall(MatDestroy(&M));
  PetscFunctionReturn(0);
}

}  // namespace

Runtime::Runtime(int argc, char** argv) {
  check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
}

Runtime::~Runtime() { PetscFinalize(); }

ScopedStage::ScopedStage(const char* name) {
  // Stages are registered once per name and pushed again on later uses.
  static std::map<std::string, PetscLogStage> stages;
  auto found = stages.find(name);
  if (found == stages.end()) {
    PetscLogStage stage;
    check(PetscLogStageRegister(name, &stage), "PetscLogStageRegister");
    found = stages.emplace(name, stage).first;
  }
  check(PetscLogStagePush(found->second), "PetscLogStagePush");
}

ScopedStage::~ScopedStage() { PetscLogStagePop(); }

bool hasPetscOption(const char* name) {
  PetscBool found = PETSC_FALSE;
  check(PetscOptionsHasName(nullptr, nullptr, name, &found), "PetscOptionsHasName");
  return found == PETSC_TRUE;
}

LocalSolution solveRadiosity(formfactor::SparseRows rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& area, const Options& options,
                             Report& report) {
  LocalSolution solution;
  solution.firstPatch = rows.firstRow;
  solution.radiosity.resize(rows.rowCount());
  solution.irradiance.resize(rows.rowCount());
  if (options.samplesPerRow > 0) solution.radiosityStderr.assign(rows.rowCount(), Rgb{0, 0, 0});
  // (rows is released once assembled: pass it with std::move unless the caller needs it after)
  report = Report{};
  ChannelFailure failure;
  RunState run;
  check(solveChannels(rows, globalPatchCount, reflectance, emission, area, options, solution,
                      report, run, failure),
        "the solve");
  if (run.saveFailure) std::rethrow_exception(run.saveFailure);
  if (run.stopped) throw SolveStopped();
  if (!failure.message.empty()) throw Error(exit_code::kNumerical, failure.message);
  return solution;
}

}  // namespace radiosity::solve
