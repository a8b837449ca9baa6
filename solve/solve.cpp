// solveRadiosity. M = diag(w) F is assembled once (MPIAIJ; w = 1, or the patch areas for CG's
// symmetric form) and every channel iterates on it through a ChannelSystem: a shell operator,
// or M turned in place into the explicit form and back; never a copy per channel. The channels
// are solved in turn (channel_solve.h), then the error of B is estimated (solution_error.h) and,
// without --rtol, the channels are solved further until the solver's error is small beside it.
// PETSc-style functions return PetscErrorCode; the C++ entry point turns failures into
// exceptions after cleaning up.
#include <petscksp.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <variant>

#include "core/channels.h"
#include "solve/assemble.h"
#include "solve/channel_plan.h"
#include "solve/channel_solve.h"
#include "solve/petsc_check.h"
#include "solve/shared_system.h"
#include "solve/solution_error.h"
#include "solve/solve.h"

namespace radiosity::solve {

namespace {

PetscErrorCode solveChannels(FormFactorRows& rows, int64_t globalCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& localArea, const Options& options,
                             LocalSolution& solution, Report& report, RunState& run,
                             ChannelFailure& failure) {
  SharedSystem s;
  PetscFunctionBeginUser;
  // CG iterates on the symmetric form, so it stores S = diag(area) F; the others F itself.
  const bool symmetricForm = options.solver == Solver::kCg;
  const formfactor::SampleTally* tally = std::get_if<formfactor::SampleTally>(&rows);
  PetscCheck(!options.rebuildTally ||
                 (tally && options.solver != Solver::kCg && options.solver != Solver::kGaussSeidel),
             PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "the tally can be rebuilt only from F assembled from it and left as it is");
  PetscCall(std::visit(
      [&](const auto& r) {
        return assembleRows(PETSC_COMM_WORLD, r, symmetricForm ? &localArea : nullptr, &s.M);
      },
      rows));
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
  const ChannelPlan plan = planChannels(
      PETSC_COMM_WORLD, std::visit([](const auto& r) { return formfactor::rowSums(r); }, rows),
      reflectance, emission);
  run.samples = tally ? tally->samples : 0;
  run.formFactors = s.M;
  rows = formfactor::SparseRows();  // F lives in M from here on: stored once
  report.leftOut = plan.leftOut();
  report.solver = solverName(options.solver);
  if (options.resume) report.history = options.resume->history;
  WorkCount work;
  const double start = MPI_Wtime();
  const bool estimate = options.samplesPerRow > 0;
  VarianceModel model;
  if (estimate) model.resize(solution.radiosity.size());
  std::array<ChannelResult, 3> results;

  // 1. Every channel that needs a solve, to rtol (the user's, or where the adaptive one starts):
  // first all of them together, one pass over F per iteration for all (solve/channel_block.cpp),
  // then each from the block's iterate (one product to check it, more only if it falls short).
  std::array<Vec, 3> blockIterate{};
  BlockOutcome block;
  {
    std::vector<int> together;
    for (int c = 0; c < 3; ++c) {
      if (!plan.needsSolve(c) || plan.singular[c]) continue;
      if (options.resume && options.resume->channelState[c] == 2) continue;
      PetscReal norm;
      PetscCall(fillChannel(s.E, emission, c));
      PetscCall(VecNorm(s.E, NORM_2, &norm));
      if (norm > 0) together.push_back(c);  // (E_c = 0: B_c = 0, left to the channel's solve)
    }
    MatInfo info;
    PetscCall(MatGetInfo(s.M, MAT_GLOBAL_SUM, &info));
    bool inOneBlock = false;
    PetscCall(solvesChannelsTogether(options.solver, static_cast<int>(together.size()),
                                     info.nz_used / static_cast<double>(globalCount), &inOneBlock));
    if (together.size() >= 2 && inOneBlock) {
      for (int c : together) {
        if (!options.resume || options.resume->channelState[c] != 1) continue;
        PetscCall(VecDuplicate(s.E, &blockIterate[c]));
        PetscCall(fillChannel(blockIterate[c], options.resume->radiosity, c));
      }
      PetscCall(solveChannelBlock(s, together, reflectance, emission, blockIterate, options.rtol,
                                  options, start, work, solution, report, run, block));
      results[together.front()].iterations += block.iterations;
    }
  }
  for (int c = 0; c < 3 && failure.message.empty() && !run.stopped; ++c) {
    if (plan.singular[c]) {
      failure.message = std::string("the ") + kChannelNames[c] +
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
      Vec from = blockIterate[c] ? blockIterate[c] : resumed ? s.B : nullptr;
      PetscCall(solveOneChannel(s.M, s.rho, s.weight, s.E, s.area, s.B, from, c, options.rtol,
                                options, start, work, solution, report, run, failure, results[c],
                                blockIterate[c] && block.converged ? &block : nullptr));
      if (run.stopped) break;
    }
    PetscCall(readChannelResults(s, c, solution));
    // (B = E has no sampling error)
    if (estimate && !plan.noReflection[c] && !options.exactRows)
      PetscCall(modelChannelVariance(s, reflectance, c, options.samplesPerRow, model));
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

  // 2. The error of B: the sampling model scaled to the estimator's real error, and the
  // discretisation error.
  // (a scene without reflection has B = E exactly: nothing to estimate, no rays to spend)
  const bool reflects = !plan.noReflection[0] || !plan.noReflection[1] || !plan.noReflection[2];
  if (finished && estimate && reflects) {
    PetscCall(estimateSolutionError(s, plan, results, model, reflectance, localArea, options,
                                    solution, report));
  }

  // 3. Adaptive tolerance: no solver work the sampling error does not need, and none short of
  // what it needs: go on where the solver's error is above a tenth of the sampling error.
  const bool anySolved = results[0].solved || results[1].solved || results[2].solved;
  if (finished && estimate && options.adaptiveRtol && anySolved) {
    std::array<double, 3> rtol{options.rtol, options.rtol, options.rtol};
    // What the solver's error must stay a tenth of: the sampling error, or with exact rows,
    // which have none, the error estimated (discretisation).
    const std::array<double, 3>& target = options.exactRows ? report.errorB : report.samplingErrorB;
    const char* targetName = options.exactRows ? "estimated error" : "sampling error";
    for (int round = 0; round < 4 && failure.message.empty() && !run.stopped; ++round) {
      const std::array<double, 3> error = solverErrors(results, localArea, reflectance, solution);
      bool more = false;
      for (int c = 0; c < 3 && failure.message.empty() && !run.stopped; ++c) {
        const double allowed = 0.1 * target[c];
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
        PetscCall(readChannelResults(s, c, solution));
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
                    "error bound, %.2g, is below a tenth of the %s, %.2g)",
                    largestRtol,
                    *std::max_element(report.solverError.begin(), report.solverError.end()),
                    targetName, report.relativeStderr);
      report.toleranceNote = note;
      for (int c = 0; c < 3; ++c) {
        if (results[c].solved && report.solverError[c] > 0.1 * target[c]) {
          std::snprintf(note, sizeof note,
                        "no --rtol given: the %s channel's solver error bound (%.2g) stays above "
                        "a tenth of its %s (%.2g) at relative residual %.0e",
                        kChannelNames[c], report.solverError[c], targetName, target[c], rtol[c]);
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

  // F as sampled, back for the caller's final checkpoint or next round (the matrix goes).
  if (options.rebuildTally && options.tallyBack)
    PetscCall(tallyFromMatrix(s.M, run.samples, options.tallyBack));
  for (Vec& v : blockIterate)
    if (v) PetscCall(VecDestroy(&v));
  for (Vec* v : {&s.rho, &s.E, &s.B, &s.H, &s.weight, &s.area, &s.emitter}) {
    if (*v) PetscCall(VecDestroy(v));
  }
  PetscCall(MatDestroy(&s.M));
  PetscFunctionReturn(0);
}

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
