// The PETSc adapter. M = diag(w) F is assembled once (MPIAIJ; w = 1, or the patch areas for
// CG's symmetric form) and every channel iterates on it through a ChannelSystem: a shell
// operator, or M turned in place into the explicit form and back; never a copy per channel.
// PETSc-style functions below return PetscErrorCode; the C++ entry point turns failures into
// exceptions after cleaning up.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <string>

#include "io/store/light_error.h"
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

// One channel's solve, as it ended.
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

// Solves channel c to `rtol`, from `start` (a full-length B) or from b. Leaves B in `B`.
PetscErrorCode solveOneChannel(Mat M, Vec rho, Vec weight, Vec E, Vec area, Vec B, Vec start,
                               int c, double rtol, const Options& options, double startTime,
                               WorkCount& work, const LocalSolution& solution, Report& report,
                               RunState& run, ChannelFailure& failure, ChannelResult& result) {
  ChannelSystem system;
  ChannelOutcome outcome;
  Vec r;
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
  HistoryRecorder recorder{&report.history, c, startTime, system.emissionNorm,
                           iterationsRecorded(report.history, c)};
  int64_t iterations = 0;
  while (true) {
    outcome = ChannelOutcome();
    if (options.solver == "southwell") {
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
  PetscCall(VecDuplicate(system.rhs, &r));
  PetscCall(channelResidual(system, system.solution, r, work));
  PetscCall(VecNorm(r, NORM_2, &residualNorm));
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
    result.condition = system.contraction < 1
                           ? (1 + system.contraction) / (1 - system.contraction)
                           : std::numeric_limits<double>::infinity();
    result.conditionSource = "bound (1 + q)/(1 - q) of the Jacobi-scaled operator";
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

// Copies channel `from` into channel `to` of per-row triples.
void copyChannel(std::vector<Rgb>& values, int from, int to) {
  for (Rgb& v : values) v[to] = v[from];
}

// Everything the channels share while they are solved: the stored matrix and its vectors.
struct SharedSystem {
  Mat M = nullptr;
  Vec rho = nullptr, E = nullptr, B = nullptr, H = nullptr, weight = nullptr, area = nullptr;
  Vec emitter = nullptr;  ///< 1 where a patch emits, else 0
};

// The variance model of every channel (sampling_error.h): each row's variance of H in two
// parts, and each part propagated to B.
struct VarianceModel {
  std::vector<Rgb> indirect, direct, indirectB, directB;
  void resize(size_t rows) {
    for (auto* v : {&indirect, &direct, &indirectB, &directB}) v->assign(rows, Rgb{0, 0, 0});
  }
  void copyChannel(int from, int to) {
    for (auto* v : {&indirect, &direct, &indirectB, &directB})
      if (!v->empty()) solve::copyChannel(*v, from, to);
  }
};

// B and H of channel c into the solution; with a model, its variances too.
PetscErrorCode readChannelResults(const SharedSystem& s, const std::vector<Rgb>& reflectance,
                                  int c, int64_t samples, LocalSolution& solution,
                                  VarianceModel* model) {
  PetscFunctionBeginUser;
  PetscCall(readChannel(s.B, solution.radiosity, c));
  PetscCall(irradiance(s.M, s.weight, s.B, s.H));
  PetscCall(readChannel(s.H, solution.irradiance, c));
  if (model) {
    Vec indirect, direct, propagated;
    for (Vec* v : {&indirect, &direct, &propagated}) PetscCall(VecDuplicate(s.B, v));
    PetscCall(fillChannel(s.rho, reflectance, c));
    PetscCall(rowVarianceModel(s.M, s.weight, s.B, s.emitter, samples, indirect, direct));
    PetscCall(readChannel(indirect, model->indirect, c));
    PetscCall(readChannel(direct, model->direct, c));
    PetscCall(propagateVariance(s.M, s.weight, s.rho, s.area, indirect, propagated));
    PetscCall(readChannel(propagated, model->indirectB, c));
    PetscCall(propagateVariance(s.M, s.weight, s.rho, s.area, direct, propagated));
    PetscCall(readChannel(propagated, model->directB, c));
    for (Vec* v : {&indirect, &direct, &propagated}) PetscCall(VecDestroy(v));
  }
  PetscFunctionReturn(0);
}

// The solver's error bound of each channel in the light measure (io/store/light_error.h).
std::array<double, 3> solverErrors(const std::array<ChannelResult, 3>& results,
                                   const std::vector<double>& area,
                                   const std::vector<Rgb>& reflectance,
                                   const LocalSolution& solution) {
  const Rgb bound{results[0].absoluteBound, results[1].absoluteBound, results[2].absoluteBound};
  const std::vector<Rgb> errors(solution.radiosity.size(), bound);
  return relativeLightError(PETSC_COMM_WORLD, area, reflectance, solution.radiosity, errors);
}

PetscErrorCode solveChannels(formfactor::SparseRows& rows, int64_t globalCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& localArea, const Options& options,
                             LocalSolution& solution, Report& report, RunState& run,
                             ChannelFailure& failure) {
  SharedSystem s;
  PetscFunctionBeginUser;
  // CG iterates on the symmetric form, so it stores S = diag(area) F; the others F itself.
  const bool symmetricForm = options.solver == "cg";
  PetscCall(assembleRows(PETSC_COMM_WORLD, rows, symmetricForm ? &localArea : nullptr, &s.M));
  PetscInt rowsInAll, columnsInAll;
  PetscCall(MatGetSize(s.M, &rowsInAll, &columnsInAll));
  PetscCheck(rowsInAll == globalCount, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
             "the ranks' rows add up to %" PetscInt_FMT " patches, not %" PetscInt_FMT, rowsInAll,
             static_cast<PetscInt>(globalCount));
  PetscCall(MatCreateVecs(s.M, &s.B, &s.E));
  for (Vec* v : {&s.rho, &s.H, &s.weight, &s.area}) PetscCall(VecDuplicate(s.E, v));
  PetscCall(fillValues(s.area, localArea));
  if (symmetricForm) {
    PetscCall(VecCopy(s.area, s.weight));
  } else {
    PetscCall(VecSet(s.weight, 1.0));
  }
  {
    std::vector<double> mask(emission.size());
    for (size_t r = 0; r < emission.size(); ++r) {
      const Rgb& e = emission[r];
      mask[r] = e[0] > 0 || e[1] > 0 || e[2] > 0 ? 1.0 : 0.0;
    }
    PetscCall(VecDuplicate(s.E, &s.emitter));
    PetscCall(fillValues(s.emitter, mask));
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
  const bool estimate = options.samplesPerRow > 0;
  VarianceModel model;
  if (estimate) model.resize(solution.radiosity.size());
  std::array<ChannelResult, 3> results;

  // 1. Every channel that needs a solve, to rtol (the user's, or where the adaptive one starts).
  for (int c = 0; c < 3 && failure.message.empty() && !run.stopped; ++c) {
    if (plan.singular[c]) {
      failure.message = std::string("the ") + kChannelName[c] +
                        " channel is singular: every patch of a closed scene reflects all the "
                        "light it gets (rho = 1), so I - F has no inverse; lower the reflectance";
      break;
    }
    if (plan.sameAs[c] >= 0) continue;  // copied below
    PetscCall(fillChannel(s.E, emission, c));
    if (plan.noReflection[c]) {
      PetscCall(VecCopy(s.E, s.B));  // B = E; H = F E all the same
    } else if (options.resume && options.resume->channelState[c] == 2) {
      PetscCall(fillChannel(s.B, options.resume->radiosity, c));  // solved before the restart
    } else {
      const bool resumed = options.resume && options.resume->channelState[c] == 1;
      if (resumed) PetscCall(fillChannel(s.B, options.resume->radiosity, c));
      PetscCall(fillChannel(s.rho, reflectance, c));
      PetscCall(solveOneChannel(s.M, s.rho, s.weight, s.E, s.area, s.B, resumed ? s.B : nullptr, c,
                                options.rtol, options, start, work, solution, report, run,
                                failure, results[c]));
      if (run.stopped) break;
    }
    // (B = E has no sampling error)
    PetscCall(readChannelResults(s, reflectance, c, options.samplesPerRow, solution,
                                 estimate && !plan.noReflection[c] ? &model : nullptr));
    run.channelState[c] = 2;
  }
  auto copySameChannels = [&] {
    for (int c = 0; c < 3; ++c) {
      if (plan.sameAs[c] < 0) continue;
      for (auto* values : {&solution.radiosity, &solution.irradiance, &solution.radiosityStderr})
        if (!values->empty()) copyChannel(*values, plan.sameAs[c], c);
      model.copyChannel(plan.sameAs[c], c);
      run.channelState[c] = 2;
    }
  };
  const bool finished = failure.message.empty() && !run.stopped;
  if (finished) copySameChannels();

  // 2. The sampling error: the model, scaled to the estimator's real error.
  // (a scene without reflection has B = E exactly: nothing to estimate, no rays to spend)
  const bool reflects = !plan.noReflection[0] || !plan.noReflection[1] || !plan.noReflection[2];
  if (finished && estimate && reflects) {
    if (options.calibrate)
      report.calibration = options.calibrate(solution.radiosity, model.indirect, model.direct);
    std::vector<Rgb> irradianceStderr(solution.radiosity.size(), Rgb{0, 0, 0});
    for (size_t r = 0; r < solution.radiosity.size(); ++r) {
      for (int k = 0; k < 3; ++k) {
        const double error = std::sqrt(report.calibration.indirect[k] * model.indirectB[r][k] +
                                       report.calibration.direct[k] * model.directB[r][k]);
        solution.radiosityStderr[r][k] = std::isfinite(error) ? error : 0.0;
        // B = E + ρ H: H's error is B's over ρ (only reflecting patches count in the measure).
        if (reflectance[r][k] > 0) irradianceStderr[r][k] = error / reflectance[r][k];
      }
    }
    report.samplingErrorB = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                               solution.radiosity, solution.radiosityStderr);
    report.samplingErrorH = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                               solution.irradiance, irradianceStderr);
    report.samplingShare =
        *std::max_element(report.samplingErrorB.begin(), report.samplingErrorB.end());
    report.errorB = report.samplingErrorB;
    report.errorH = report.samplingErrorH;

    // The discretisation error: each row's error of H, carried through the bounces by sweeps
    // δB ← ρ δH + ρ F δB until the light left is below 5 % (q^n), then combined per patch
    // with the sampling error in quadrature (its own noise taken out).
    if (options.discretisation) {
      std::vector<Rgb> errorH, varianceH;
      options.discretisation(solution.irradiance, errorH, varianceH);
      solution.radiosityDiscretisation.assign(solution.radiosity.size(), Rgb{0, 0, 0});
      Vec local, swept, gathered;
      for (Vec* v : {&local, &swept, &gathered}) PetscCall(VecDuplicate(s.B, v));
      for (int c = 0; c < 3; ++c) {
        if (plan.noReflection[c]) continue;
        PetscCall(fillChannel(s.rho, reflectance, c));
        PetscCall(fillChannel(local, errorH, c));
        PetscCall(VecPointwiseMult(local, local, s.rho));
        PetscCall(VecCopy(local, swept));
        const double q = std::max(results[c].contraction, results[plan.sameAs[c] >= 0 ? plan.sameAs[c] : c].contraction);
        const int sweeps =
            q > 0 && q < 1 ? std::clamp(static_cast<int>(std::ceil(std::log(0.05) / std::log(q))), 1, 50)
                           : 50;
        for (int sweep = 0; sweep < sweeps; ++sweep) {
          PetscCall(irradiance(s.M, s.weight, swept, gathered));
          PetscCall(VecPointwiseMult(gathered, gathered, s.rho));
          PetscCall(VecWAXPY(swept, 1.0, local, gathered));
        }
        PetscCall(readChannel(swept, solution.radiosityDiscretisation, c));
      }
      for (Vec* v : {&local, &swept, &gathered}) PetscCall(VecDestroy(v));
      std::vector<Rgb> discretisation(solution.radiosity.size()), total(solution.radiosity.size()),
          totalH(solution.radiosity.size(), Rgb{0, 0, 0});
      for (size_t r = 0; r < solution.radiosity.size(); ++r) {
        for (int k = 0; k < 3; ++k) {
          const double rho = reflectance[r][k], d = solution.radiosityDiscretisation[r][k];
          const double squared = std::max(0.0, d * d - rho * rho * varianceH[r][k]);
          discretisation[r][k] = std::sqrt(squared);
          // (stored with its noise taken out, signed: the estimated true B minus B)
          solution.radiosityDiscretisation[r][k] = std::copysign(discretisation[r][k], d);
          total[r][k] = std::sqrt(squared + std::pow(solution.radiosityStderr[r][k], 2));
          if (rho > 0) totalH[r][k] = total[r][k] / rho;
        }
      }
      report.discretisationErrorB = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                                       solution.radiosity, discretisation);
      report.errorB =
          relativeLightError(PETSC_COMM_WORLD, localArea, reflectance, solution.radiosity, total);
      report.errorH = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                         solution.irradiance, totalH);
      report.discretisationShare = *std::max_element(report.discretisationErrorB.begin(),
                                                     report.discretisationErrorB.end());
    }
    report.relativeStderr = *std::max_element(report.errorB.begin(), report.errorB.end());
  }

  // 3. Adaptive tolerance: no solver work the sampling error does not need, and none short of
  // what it needs: go on where the solver's error is above a tenth of the sampling error.
  const bool anySolved = results[0].solved || results[1].solved || results[2].solved;
  if (finished && estimate && options.adaptiveRtol && anySolved) {
    std::array<double, 3> rtol{options.rtol, options.rtol, options.rtol};
    for (int round = 0; round < 4 && failure.message.empty() && !run.stopped; ++round) {
      const std::array<double, 3> error = solverErrors(results, localArea, reflectance, solution);
      bool more = false;
      for (int c = 0; c < 3 && failure.message.empty() && !run.stopped; ++c) {
        const double allowed = 0.1 * report.samplingErrorB[c];
        if (!results[c].solved || error[c] <= allowed || rtol[c] <= kFinestAdaptiveRtol) continue;
        // The bound falls about like the residual: aim at half the allowance.
        const double factor = error[c] > 0 && allowed > 0 ? 0.5 * allowed / error[c] : 1e-2;
        rtol[c] = std::max(kFinestAdaptiveRtol, rtol[c] * std::clamp(factor, 1e-4, 0.5));
        PetscCall(fillChannel(s.E, emission, c));
        PetscCall(fillChannel(s.rho, reflectance, c));
        PetscCall(fillChannel(s.B, solution.radiosity, c));
        run.channelState[c] = 1;
        PetscCall(solveOneChannel(s.M, s.rho, s.weight, s.E, s.area, s.B, s.B, c, rtol[c], options,
                                  start, work, solution, report, run, failure, results[c]));
        if (run.stopped || !failure.message.empty()) break;
        // (the model barely moves with the last digits of B: kept)
        PetscCall(readChannelResults(s, reflectance, c, 0, solution, nullptr));
        run.channelState[c] = 2;
        more = true;
      }
      if (!more) break;
    }
    if (failure.message.empty() && !run.stopped) {
      copySameChannels();
      report.solverError = solverErrors(results, localArea, reflectance, solution);
      const double largestRtol = *std::max_element(rtol.begin(), rtol.end());
      char note[256];
      std::snprintf(note, sizeof note,
                    "no --rtol given: a relative residual of %.0e was enough (the solver's "
                    "error bound, %.2g, is below a tenth of the sampling error, %.2g)",
                    largestRtol,
                    *std::max_element(report.solverError.begin(), report.solverError.end()),
                    report.relativeStderr);
      report.toleranceNote = note;
      for (int c = 0; c < 3; ++c) {
        if (results[c].solved && report.solverError[c] > 0.1 * report.samplingErrorB[c]) {
          std::snprintf(note, sizeof note,
                        "no --rtol given: the %s channel's solver error bound (%.2g) stays above "
                        "a tenth of its sampling error (%.2g) at relative residual %.0e",
                        kChannelName[c], report.solverError[c], report.samplingErrorB[c], rtol[c]);
          report.toleranceNote = note;
        }
      }
    }
  } else if (finished) {
    report.solverError = solverErrors(results, localArea, reflectance, solution);
  }

  // The report, from how each channel ended.
  for (int c = 0; c < 3; ++c) {
    const ChannelResult& result = results[c];
    report.iterations += result.iterations;
    if (!result.solved) continue;
    report.residual = std::max(report.residual, result.relativeResidual);
    report.unknowns += result.unknowns;
    report.contraction = std::max<double>(report.contraction, result.contraction);
    report.errorBound = std::max<double>(report.errorBound, result.errorBound);
    ++report.channelsSolved;
    if (result.condition > report.conditionEstimate || report.conditionSource.empty()) {
      report.conditionEstimate = std::max(report.conditionEstimate, result.condition);
      report.conditionSource = result.conditionSource;
    }
  }
  report.converged = failure.message.empty();
  report.matrixProducts = work.matrixProducts;
  report.nonzeroProducts = work.nonzeroProducts;

  for (Vec* v : {&s.rho, &s.E, &s.B, &s.H, &s.weight, &s.area, &s.emitter}) {
    if (*v) PetscCall(VecDestroy(v));
  }
  PetscCall(MatDestroy(&s.M));
  PetscFunctionReturn(0);
}

}  // namespace

Runtime::Runtime(int argc, char** argv) {
  check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
  // A closed pipe (`radiosity info x.h5 | head`) ends the program quietly, as for any tool,
  // instead of PETSc's handler reporting a crash and aborting MPI.
  std::signal(SIGPIPE, SIG_DFL);
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

std::vector<std::string> unusedPetscOptions() {
  PetscInt count = 0;
  char **names = nullptr, **values = nullptr;
  check(PetscOptionsLeftGet(nullptr, &count, &names, &values), "PetscOptionsLeftGet");
  std::vector<std::string> unused;
  for (PetscInt k = 0; k < count; ++k) unused.push_back(std::string("-") + names[k]);
  check(PetscOptionsLeftRestore(nullptr, &count, &names, &values), "PetscOptionsLeftRestore");
  return unused;
}

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
