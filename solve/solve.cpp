// solveRadiosity. M = diag(w) F is assembled once (MPIAIJ; w = 1, or the patch areas for CG's
// symmetric form) and every channel iterates on it through a ChannelSystem: a shell operator,
// or M turned in place into the explicit form and back; never a copy per channel. The channels
// are solved in turn (channel_solve.h), then the error of B is estimated (solution_error.h) and,
// without --rtol, the channels are solved further until the solver's error is small beside it.
// PETSc-style functions return PetscErrorCode; the C++ entry point turns failures into
// exceptions, every PETSc object being owned (petsc_handles.h) and so freed on any path out.
#include <petscksp.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>
#include <variant>

#include "core/channels.h"
#include "solve/assemble.h"
#include "solve/channel_plan.h"
#include "solve/channel_solve.h"
#include "solve/petsc_check.h"
#include "solve/petsc_handles.h"
#include "solve/shared_system.h"
#include "solve/solution_error.h"
#include "solve/solve.h"

namespace radiosity::solve {

namespace {

// The steps of solveRadiosity on the PETSc side, in order (run()): the shared system, every
// channel to rtol (first together where that pays), the channels equal to one solved, the error
// of B, the adaptive tolerance, the report. The objects are owned: they go with the object on
// every way out, an early PetscCall return included.
class ChannelsSolve {
 public:
  ChannelsSolve(int64_t globalCount, const std::vector<Rgb>& reflectance,
                const std::vector<Rgb>& emission, const std::vector<double>& localArea,
                const Options& options, LocalSolution& solution, Report& report)
      : globalCount_(globalCount),
        reflectance_(reflectance),
        emission_(emission),
        localArea_(localArea),
        options_(options),
        solution_(solution),
        report_(report),
        context_{s_, reflectance, emission, options, 0, solution, work_, report.history, run_} {}

  PetscErrorCode run(FormFactorRows& rows) {
    PetscFunctionBeginUser;
    PetscCall(setUp(rows));
    // 1. Every channel that needs a solve, to rtol (the user's, or where the adaptive one
    // starts): first all of them together, one pass over F per iteration for all
    // (solve/channel_block.cpp), then each from the block's iterate (one product to check it,
    // more only if it falls short).
    PetscCall(solveTogether());
    PetscCall(solveEach());
    const bool finished = going();
    if (finished) copySameChannels();
    // 2. The error of B: the sampling model scaled to the estimator's real error, and the
    // discretisation error.
    // (a scene without reflection has B = E exactly: nothing to estimate, no rays to spend)
    const bool reflects =
        !plan_.noReflection[0] || !plan_.noReflection[1] || !plan_.noReflection[2];
    if (finished && estimate_ && reflects) {
      releaseFreedHeap();  // (the Krylov bases are freed: the estimates reuse no pages of theirs)
      PetscCall(modelVariance());
      PetscCall(estimateSolutionError({s_, plan_, reflectance_, localArea_, options_},
                                      std::move(model_), solution_, report_));
    }
    // 3. Adaptive tolerance: no solver work the sampling error does not need, and none short of
    // what it needs.
    const bool anySolved = results_[0].solved || results_[1].solved || results_[2].solved;
    if (finished && estimate_ && options_.adaptiveRtol && anySolved) {
      PetscCall(tightenTolerance());
    } else if (finished) {
      report_.solverError = solverErrors(results_, localArea_, reflectance_, solution_);
    }
    summarise();
    // F's one store, back for the caller's final checkpoint or next round (the matrix goes).
    if (options_.handBackRows && options_.rowsBack) {
      Mat M = s_.M.release();
      run_.formFactors = nullptr;
      PetscCall(takeRowsBack(&M, s_.lent));
      *options_.rowsBack = std::move(s_.lent);
    }
    PetscFunctionReturn(0);
  }

  const RunState& runState() const { return run_; }
  const ChannelFailure& failure() const { return failure_; }

 private:
  bool going() const { return failure_.message.empty() && !run_.stopped; }
  bool resumedAs(int c, int state) const {
    return options_.resume && options_.resume->channelState[c] == state;
  }

  // M and its vectors, and the plan: what the scene lets us leave out.
  PetscErrorCode setUp(FormFactorRows& rows) {
    // CG iterates on the symmetric form, so it stores S = diag(area) F; the others F itself.
    const bool symmetricForm = options_.solver == Solver::kCg;
    const bool store = std::holds_alternative<formfactor::SplitRows>(rows);
    PetscFunctionBeginUser;
    PetscCheck(!options_.handBackRows || (store && options_.solver != Solver::kCg &&
                                          options_.solver != Solver::kGaussSeidel),
               PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "F's store can be handed back only where M is made on it and left as it is");
    // (the row sums first: F's one store goes into the shared system)
    const std::vector<double> rowSums =
        std::visit([](const auto& r) { return formfactor::rowSums(r); }, rows);
    PetscCall(setUpSharedSystem(rows, globalCount_, localArea_, emission_, symmetricForm,
                                needsExplicitMatrix(options_.solver), &s_));
    // Leave out what the scene does not need: channels without reflection (B = E), channels
    // equal to one already solved, and black patches inside a channel (ChannelSystem).
    plan_ = planChannels(PETSC_COMM_WORLD, rowSums, reflectance_, emission_);
    if (options_.handBackRows) run_.formFactors = &s_.lent;
    rows = formfactor::SparseRows();  // F lives in M from here on: stored once
    report_.leftOut = plan_.leftOut(options_.channels, options_.hiddenPatches);
    report_.solver = solverName(options_.solver);
    if (options_.resume) report_.history = options_.resume->history;
    context_.startTime = MPI_Wtime();
    estimate_ = options_.samplesPerRow > 0;
    PetscFunctionReturn(0);
  }

  // The channels with light to reflect solved together, where the solver and F make it pay.
  PetscErrorCode solveTogether() {
    std::vector<int> together;
    PetscFunctionBeginUser;
    for (int c = 0; c < 3; ++c) {
      if (!plan_.needsSolve(c) || plan_.singular[c] || resumedAs(c, 2)) continue;
      PetscReal norm;
      PetscCall(fillChannel(s_.E, emission_, c));
      PetscCall(VecNorm(s_.E, NORM_2, &norm));
      if (norm > 0) together.push_back(c);  // (E_c = 0: B_c = 0, left to the channel's solve)
    }
    MatInfo info;
    PetscCall(MatGetInfo(s_.M, MAT_GLOBAL_SUM, &info));
    bool inOneBlock = false;
    PetscCall(solvesChannelsTogether(options_.solver, static_cast<int>(together.size()),
                                     info.nz_used / static_cast<double>(globalCount_),
                                     &inOneBlock));
    if (together.size() < 2 || !inOneBlock) PetscFunctionReturn(0);
    for (int c : together) {
      if (!resumedAs(c, 1)) continue;
      PetscCall(VecDuplicate(s_.E, blockIterate_[c].out()));
      PetscCall(fillChannel(blockIterate_[c], options_.resume->radiosity, c));
    }
    PetscCall(solveChannelBlock(context_, together, options_.rtol, blockIterate_, &block_));
    results_[together.front()].iterations += block_.iterations;
    PetscFunctionReturn(0);
  }

  // Each channel in turn: left out, copied, resumed done, or solved (from the block's iterate).
  PetscErrorCode solveEach() {
    PetscFunctionBeginUser;
    for (int c = 0; c < 3 && going(); ++c) {
      if (plan_.singular[c]) {
        failure_.message = std::string("the ") + channelName(c, options_.channels) +
                           " channel is singular: every patch of a closed scene reflects all the "
                           "light it gets (rho = 1), so I - F has no inverse; lower the "
                           "reflectance";
        break;
      }
      if (plan_.sameAs[c] >= 0) continue;  // copied below
      PetscCall(fillChannel(s_.E, emission_, c));
      if (plan_.noReflection[c]) {
        PetscCall(VecCopy(s_.E, s_.B));  // B = E; H = F E all the same
      } else if (resumedAs(c, 2)) {
        PetscCall(fillChannel(s_.B, options_.resume->radiosity, c));  // solved before the restart
      } else {
        const bool resumed = resumedAs(c, 1);
        if (resumed) PetscCall(fillChannel(s_.B, options_.resume->radiosity, c));
        PetscCall(fillChannel(s_.rho, reflectance_, c));
        ChannelTask task{c, options_.rtol};
        task.start = blockIterate_[c] ? blockIterate_[c].get() : resumed ? s_.B.get() : nullptr;
        task.block = blockIterate_[c] && block_.converged ? &block_ : nullptr;
        PetscCall(solveChannel(task));
        if (run_.stopped) break;
      }
      PetscCall(readChannelResults(s_, c, solution_));
      run_.channelState[c] = 2;
    }
    PetscFunctionReturn(0);
  }

  PetscErrorCode solveChannel(const ChannelTask& task) {
    ChannelEnd end;
    PetscFunctionBeginUser;
    PetscCall(solveOneChannel(context_, task, &end));
    takeChannelEnd(end, results_[task.channel], failure_);
    PetscFunctionReturn(0);
  }

  void copySameChannels() {
    for (int c = 0; c < 3; ++c) {
      if (plan_.sameAs[c] < 0) continue;
      for (auto* values : {&solution_.radiosity, &solution_.irradiance, &solution_.radiosityStderr})
        if (!values->empty()) copyChannel(*values, plan_.sameAs[c], c);
      run_.channelState[c] = 2;
    }
  }

  // The sampling variance model of every channel, from its B, once all are solved: made then
  // and not after each channel's solve, so that its four arrays are not held under the later
  // channels' Krylov bases (the run's memory peak).
  PetscErrorCode modelVariance() {
    PetscFunctionBeginUser;
    model_.resize(solution_.radiosity.size());
    for (int c = 0; c < 3; ++c) {
      // (B = E has no sampling error; exact rows have none)
      if (plan_.sameAs[c] >= 0 || plan_.noReflection[c] || options_.exactRows) continue;
      PetscCall(fillChannel(s_.B, solution_.radiosity, c));
      PetscCall(modelChannelVariance(s_, reflectance_, c, options_.samplesPerRow, model_));
    }
    for (int c = 0; c < 3; ++c)
      if (plan_.sameAs[c] >= 0) model_.copyChannel(plan_.sameAs[c], c);
    PetscFunctionReturn(0);
  }

  // Go on where the solver's error is above a tenth of the sampling error (with exact rows,
  // which have none, of the error estimated: discretisation), for a few rounds.
  PetscErrorCode tightenTolerance() {
    std::array<double, 3> rtol{options_.rtol, options_.rtol, options_.rtol};
    const std::array<double, 3>& target =
        options_.exactRows ? report_.errorB : report_.samplingErrorB;
    PetscFunctionBeginUser;
    for (int round = 0; round < 4 && going(); ++round) {
      const std::array<double, 3> error =
          solverErrors(results_, localArea_, reflectance_, solution_);
      bool more = false;
      for (int c = 0; c < 3 && going(); ++c) {
        const double allowed = 0.1 * target[c];
        if (!results_[c].solved || error[c] <= allowed || rtol[c] <= kFinestAdaptiveRtol) continue;
        // The bound falls about like the residual: aim at half the allowance.
        const double factor = error[c] > 0 && allowed > 0 ? 0.5 * allowed / error[c] : 1e-2;
        rtol[c] = std::max(kFinestAdaptiveRtol, rtol[c] * std::clamp(factor, 1e-4, 0.5));
        PetscCall(fillChannel(s_.E, emission_, c));
        PetscCall(fillChannel(s_.rho, reflectance_, c));
        PetscCall(fillChannel(s_.B, solution_.radiosity, c));
        run_.channelState[c] = 1;
        ChannelTask task{c, rtol[c]};
        task.start = s_.B;
        PetscCall(solveChannel(task));
        if (!going()) break;
        // (the model barely moves with the last digits of B: kept)
        PetscCall(readChannelResults(s_, c, solution_));
        run_.channelState[c] = 2;
        more = true;
      }
      if (!more) break;
    }
    if (going()) {
      copySameChannels();
      report_.solverError = solverErrors(results_, localArea_, reflectance_, solution_);
      noteTolerance(rtol, target);
    }
    PetscFunctionReturn(0);
  }

  // Where the adaptive tolerance stopped and why, for the log.
  void noteTolerance(const std::array<double, 3>& rtol, const std::array<double, 3>& target) {
    const char* targetName = options_.exactRows ? "estimated error" : "sampling error";
    const double largestRtol = *std::max_element(rtol.begin(), rtol.end());
    char note[256];
    std::snprintf(note, sizeof note,
                  "no --rtol given: a relative residual of %.0e was enough (the solver's "
                  "error bound, %.2g, is below a tenth of the %s, %.2g)",
                  largestRtol,
                  *std::max_element(report_.solverError.begin(), report_.solverError.end()),
                  targetName, report_.relativeStderr);
    report_.toleranceNote = note;
    for (int c = 0; c < 3; ++c) {
      if (results_[c].solved && report_.solverError[c] > 0.1 * target[c]) {
        std::snprintf(note, sizeof note,
                      "no --rtol given: the %s channel's solver error bound (%.2g) stays above "
                      "a tenth of its %s (%.2g) at relative residual %.0e",
                      channelName(c, options_.channels), report_.solverError[c], targetName,
                      target[c], rtol[c]);
        report_.toleranceNote = note;
      }
    }
  }

  // The report, from how each channel ended.
  void summarise() {
    for (int c = 0; c < 3; ++c) {
      const ChannelResult& result = results_[c];
      report_.iterations += result.iterations;
      if (!result.solved) continue;
      report_.residual = std::max(report_.residual, result.relativeResidual);
      report_.unknowns += result.unknowns;
      report_.contraction = std::max<double>(report_.contraction, result.contraction);
      report_.errorBound = std::max<double>(report_.errorBound, result.errorBound);
      ++report_.channelsSolved;
      if (result.condition > report_.conditionEstimate || report_.conditionSource.empty()) {
        report_.conditionEstimate = std::max(report_.conditionEstimate, result.condition);
        report_.conditionSource = result.conditionSource;
      }
    }
    report_.converged = failure_.message.empty();
    report_.matrixProducts = work_.matrixProducts;
    report_.nonzeroProducts = work_.nonzeroProducts;
  }

  const int64_t globalCount_;
  const std::vector<Rgb>& reflectance_;
  const std::vector<Rgb>& emission_;
  const std::vector<double>& localArea_;
  const Options& options_;
  LocalSolution& solution_;
  Report& report_;

  SharedSystem s_;
  ChannelPlan plan_;
  RunState run_;
  ChannelFailure failure_;
  WorkCount work_;
  bool estimate_ = false;
  VarianceModel model_;
  std::array<ChannelResult, 3> results_;
  std::array<OwnedVec, 3> blockIterate_;  ///< the channels solved together: their B
  BlockOutcome block_;
  ChannelContext context_;  // (after what it refers to)
};

}  // namespace

LocalSolution solveRadiosity(FormFactorRows rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& area, const Options& options,
                             Report& report) {
  LocalSolution solution;
  const int64_t rowCount = std::visit([](const auto& r) { return r.rowCount(); }, rows);
  solution.firstPatch = std::visit([](const auto& r) { return r.firstRow; }, rows);
  solution.radiosity.resize(rowCount);
  solution.irradiance.resize(rowCount);
  if (options.samplesPerRow > 0) solution.radiosityStderr.assign(rowCount, Rgb{0, 0, 0});
  // (rows is released once assembled: pass it with std::move unless the caller needs it after)
  report = Report{};
  RunState run;
  ChannelFailure failure;
  {  // (PETSc's objects are freed at the end of this scope, before anything is rethrown)
    ChannelsSolve solve(globalPatchCount, reflectance, emission, area, options, solution, report);
    check(solve.run(rows), "the solve");
    run = solve.runState();
    failure = solve.failure();
  }
  if (run.saveFailure) std::rethrow_exception(run.saveFailure);
  if (run.stopped) throw SolveStopped();
  if (!failure.message.empty()) throw Error(exit_code::kNumerical, failure.message);
  return solution;
}

}  // namespace radiosity::solve
