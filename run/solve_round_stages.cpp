// The stages of each round of `radiosity solve` (run/solve_pipeline.h): sample the form
// factors, choose the solver, repair F, solve, and with --target-error decide on another round.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>

#include "parallel/collective.h"
#include "run/derived_settings.h"
#include "run/solve_pipeline.h"
#include "run/stage_reports.h"

namespace radiosity::run {

// 3. Form factors: this rank's rows, traced against the whole scene, in pieces with a safe point
// after each; rows sampled before (a checkpoint, an earlier round) are extended.
void SolvePipeline::sample() {
  formfactor::Statistics statistics;
  // This round's solve has not started: what it will start from (a restart's saved state, the
  // last round's B) is what a checkpoint taken while sampling holds.
  state_.progress = solved_.resume ? *solved_.resume : SolveProgress();
  {
    solve::ScopedStage stage("Form factors");
    ProgressReporter progress(console_, mesh_.owned.size(),
                              plan_.exactRows ? mesh_.patchCount : plan_.rays,
                              plan_.exactRows ? "pair factors" : "rays");
    std::function<void(int64_t)> callback;
    if (!console_.isQuiet()) callback = [&](int64_t done) { progress(done); };
    double cpuSeconds = 0;  // sampling only: ranks that wait at a safe point may spin
    const bool single = storesSinglePrecision(request_, plan_, mesh_.patches);
    if (single != plan_.singlePrecision && !console_.isQuiet())
      console_.info(!single ? "form factors: F's values in double precision"
                    : plan_.exactRows
                        ? "form factors: F's values in single precision, 8 B a nonzero (exact "
                          "rows rounded onto floats with each row's sum kept: the pair factors "
                          "as accurate; --formfactor-precision double keeps 12 B)"
                        : "form factors: F's values in single precision, 8 B a nonzero "
                          "(rounding moves B far less than the sampling error; "
                          "--formfactor-precision double keeps 12 B)");
    plan_.singlePrecision = single;
    if (plan_.pairsOnce && !console_.isQuiet())
      console_.info(
          "form factors: exact rows stored once a pair (F_ji = F_ij A_i / A_j, half of "
          "F; --save-formfactors or --formfactor-precision double keep whole rows)");
    try {
      const formfactor::Options options = samplingOptions(request_, plan_);
      formFactors_.store = sampleOwnedRows(
          {comm_, *tracer_, mesh_.patches, mesh_.owned, options, single, plan_.pairsOnce},
          std::move(state_.rows),
          {*safePoints_, [this](SampledRows& rows) { saveRows(rows); }, callback, &cpuSeconds},
          statistics);
    } catch (const solve::SolveStopped&) {
      throw stopped();
    }
    const std::string outcome = describeOutcome(comm_, cpuSeconds, formFactors_.store.entries);
    if (console_.ranks() > 1 && !console_.isQuiet()) console_.info(outcome);
    formFactors_.rowSums = formfactor::rowSums(formFactors_.store);
    formfactor::addRowSums(formFactors_.rowSums, statistics);
    const double earlierRounds = attributes_.stageSeconds["formfactors"];
    endStage("formfactors");
    formFactors_.rowSumHistogram =
        reportFormFactors(console_, mesh_.patches, formFactors_.rowSums, formFactors_.store.entries,
                          statistics, attributes_.stageSeconds["formfactors"] - earlierRounds,
                          formFactors_.store.singlePrecision ? 4 : 8);
  }
  formFactors_.groups =
      formfactor::groupFactors(comm_, mesh_.patches, formFactors_.store,
                               mesh_.frame.scale * mesh_.frame.scale, plan_.exactRows);
  int64_t entries = formFactors_.store.entries;
  MPI_Allreduce(MPI_IN_PLACE, &entries, 1, MPI_INT64_T, MPI_SUM, comm_);
  formFactors_.nonzerosPerRow =
      static_cast<double>(entries) / static_cast<double>(std::max<int64_t>(1, mesh_.patchCount));
  formFactors_.rays = plan_.rays;
  maxPatches_ = patchBound(plan_.rays);
  state_.rows = SampledRows();
  state_.rows.rowSamples.assign(mesh_.owned.size(), plan_.rays);
}

// 3a. The solver: the one named, or one chosen for the scene (in the first round; the later
// ones keep it). CG needs a reciprocal F.
void SolvePipeline::chooseSolver() {
  if (!request_.solver && solved_.solverChoice.empty()) {
    const solve::SolverChoice choice = solve::chooseSolver(
        formFactors_.rowSums, mesh_.local.reflectance, plan_.reciprocity, comm_);
    solved_.options.solver = choice.solver;
    solved_.solverChoice = choice.reason;
    console_.info(std::string("solve: no --solver given: ") + solve::solverName(choice.solver) +
                  ", as " + choice.reason);
  }
  if (solve::needsReciprocity(solved_.options.solver) && !plan_.reciprocity) {
    plan_.reciprocity = true;
    console_.info(std::string("solve: ") + solve::solverName(solved_.options.solver) +
                  " needs a reciprocal F (cg: a symmetric form; chebyshev: real eigenvalues): "
                  "enforcing reciprocity (as with --reciprocity)");
  }
  enforceThermalBalance();  // (again: a refinement round may have made the rows sampled)
}

// 3b. Reciprocity and sparsification: symmetrise A_i F_ij = A_j F_ji and/or drop small F_ij,
// then restore every row's sum (Lawson's least-squares correction). Only when asked for.
void SolvePipeline::repair() {
  if (!plan_.reciprocity && request_.dropThreshold <= 0) return;
  solve::ScopedStage stage("Repair form factors");
  solve::RepairReport repair;
  formFactors_.repaired =
      solve::repairFormFactors(formfactor::toFormFactors(formFactors_.store), mesh_.local.area,
                               {plan_.reciprocity, request_.dropThreshold}, repair, comm_);
  const double earlierRounds = attributes_.stageSeconds["repair"];
  endStage("repair");
  reportRepair(console_, repair, attributes_.stageSeconds["repair"] - earlierRounds);
}

// 3c. A thermal run's F balanced in place (its columns scaled to what reciprocity says they
// carry), on a copy where the rows as sampled are kept (checkpoints, --target-error): the store
// it solves on cannot be handed back, its values no longer giving the sampled sums.
solve::FormFactorRows SolvePipeline::balancedFormFactors(bool keepRows) {
  solved_.options.handBackRows = false;
  solved_.options.rowsBack = nullptr;
  formFactors_.storeHandedBack = false;
  formfactor::SplitRows balanced;
  if (keepRows) {
    balanced = formFactors_.store;
    state_.rows.values = std::move(formFactors_.store);
  } else {
    balanced = std::move(formFactors_.store);
  }
  formFactors_.store = formfactor::SplitRows();
  {
    solve::ScopedStage stage("Balance form factors");
    // (a checkpoint's F comes with where its balance ended: a sweep or two from there)
    solve::BalanceReport balance = solve::balanceColumns(
        balanced, mesh_.local.area, mesh_.patchCount, comm_, state_.rowBalance);
    state_.rowBalance = std::move(balance.rowScale);
    const double earlierRounds = attributes_.stageSeconds["repair"];
    endStage("repair");
    reportBalance(console_, balance, attributes_.stageSeconds["repair"] - earlierRounds);
  }
  if (request_.saveFormFactors) formFactors_.repaired = formfactor::toFormFactors(balanced);
  return balanced;
}

// 4. Solve (I − diag(ρ_c) F) B_c = E_c per channel, and estimate B's sampling error.
void SolvePipeline::solve() {
  solve::ScopedStage stage("Solve");
  solved_.options.resume = solved_.resume ? &*solved_.resume : nullptr;
  solved_.options.samplesPerRow = plan_.rays;
  solved_.options.exactRows = plan_.exactRows;
  solved_.options.channels = request_.thermal.empty() ? 3 : 1;
  solved_.options.hiddenPatches = std::count_if(mesh_.hidden.begin(), mesh_.hidden.end(),
                                                [](uint8_t hidden) { return hidden != 0; });
  try {
    // (a thermal run's surroundings: light that arrives from outside the scene)
    solved_.solution = solve::solveRadiosity(formFactorsToSolve(), mesh_.patchCount,
                                             mesh_.local.reflectance, emissionWithSurroundings(),
                                             mesh_.local.area, solved_.options, solved_.report);
    addSurroundingsIrradiance(solved_.solution.irradiance);
  } catch (const solve::SolveStopped&) {
    throw stopped();
  }
  const double earlierRounds = attributes_.stageSeconds["solve"];
  endStage("solve");
  reportSolve(console_, solved_.report, attributes_.stageSeconds["solve"] - earlierRounds);
  reportCalibration(console_, solved_.calibration, solved_.discretisation, solved_.report);
}

// Another round or not: with --target-error, one towards it; with --refine-rounds N, N
// refinement rounds; by default, one refinement round where it pays. True: it is set up.
bool SolvePipeline::nextRound() {
  if (!request_.formfactorsFrom.empty()) return false;  // F as it was given
  if (request_.targetError > 0) return roundTowardsTarget();
  if (request_.refineRounds >= 0)
    return state_.refinement.rounds() < request_.refineRounds &&
           refineRound("--refine-rounds " + std::to_string(request_.refineRounds));
  return refineByDefault();
}

bool SolvePipeline::mayRefineNext() const {
  if (!request_.formfactorsFrom.empty()) return false;
  if (request_.targetError > 0) return true;
  if (request_.refineRounds >= 0) return state_.refinement.rounds() < request_.refineRounds;
  return state_.refinement.rounds() == 0;  // the default: one round at most (refineByDefault)
}

// --target-error: while the estimated error is above the target, a round that reduces its larger
// part: the discretisation error by splitting the patches it comes from (within --max-patches;
// with more rays as well when the sampling error is above its share too, since every row is
// sampled again anyway), the sampling error by more rays, while rays can bring it there.
namespace {
// A refinement round must take at least a tenth off the estimated discretisation error for
// another to follow.
constexpr double kLeastProgress = 0.9;
}  // namespace

// A refinement round that did not lower the discretisation error it was taken for is not
// followed by another: each costs more than the last (every row sampled again, often at more
// rays), for no gain. (The last round refined where the rays are still its own: a rays round
// raises them.) Exact rows take no rays: their rounds go on to --max-patches. True: stalled,
// and the log says so.
bool SolvePipeline::refinementStalled() const {
  const double before = state_.refinement.lastEstimate(), d = solved_.report.discretisationShare;
  const bool justRefined =
      state_.refinement.rounds() > 0 && plan_.rays == state_.refinement.lastRays();
  if (plan_.exactRows || !justRefined || !(before > 0) || d <= kLeastProgress * before)
    return false;
  char text[600];
  std::snprintf(text, sizeof text,
                "target error %.3g not reached: refinement round %d did not lower the estimated "
                "discretisation error (%.3g before it, %.3g after; the estimate is %.3g, "
                "sampling %.3g), so no further round is taken (a finer --max-area, or more "
                "--rays from the start, changes what rounds can reach)",
                request_.targetError, state_.refinement.rounds(), before, d,
                solved_.report.relativeStderr, solved_.report.samplingShare);
  console_.warn(text);
  return true;
}

bool SolvePipeline::roundTowardsTarget() {
  const double target = request_.targetError, d = solved_.report.discretisationShare,
               s = solved_.report.samplingShare;
  if (solved_.report.relativeStderr <= target) return false;
  char text[600];
  if (refinementStalled()) return false;
  std::snprintf(text, sizeof text, "target error %.3g: estimated %.3g, discretisation %.3g", target,
                solved_.report.relativeStderr, d);
  if ((plan_.exactRows || d >= s) && refineTowards(text)) return true;
  const std::string refine =
      !roomToRefine() ? "--max-patches reached (" + std::to_string(maxPatches_) + " patches" +
                            (request_.maxPatches > 0
                                 ? ""
                                 : ", as F fits in half the memory the job's nodes give it") +
                            "; raise it, or use more nodes)"
                      : std::string("no patch left worth splitting");
  if (plan_.exactRows) {  // more rays would only repeat the same rows
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the rows of F are exact (no sampling error), so "
                  "the estimated error %.3g is the discretisation's, which rays cannot take away, "
                  "and refinement stopped: %s",
                  target, solved_.report.relativeStderr, refine.c_str());
    console_.warn(text);
    return false;
  }
  double reachable = std::pow(0.8 * target, 2) - std::pow(d, 2);
  // The discretisation estimate carries its own noise in quadrature, which its rays take away
  // (solve/discretisation_error.h: at few rays a patch it can exceed the error). Only a
  // well-measured one (256 rays a patch, from 1024 samples, or at the rays of a round that
  // measured it again) is grounds to give up; before that, aim the sampling error at half the
  // target and measure again, once. (At 10^6 patches a second such round doubled 791 rays to
  // 1,582 for an estimate that the first had moved by 7 %.)
  const bool wellMeasured = solve::discretisationRays(plan_.rays) >= 256 ||
                            (measuredAgainAt_ > 0 && plan_.rays >= measuredAgainAt_);
  if (!wellMeasured) reachable = std::max(reachable, std::pow(0.4 * target, 2));
  if (reachable <= 0.04 * std::pow(target, 2)) {
    if (refineTowards("target error: the discretisation error leaves rays no room")) return true;
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the estimated error is %.3g, of which the "
                  "discretisation error (%.3g) is more than rays can take away, and refinement "
                  "stopped: %s",
                  target, solved_.report.relativeStderr, d, refine.c_str());
    console_.warn(text);
    return false;
  }
  const int64_t next = nextRayCount(plan_.rays, s, std::sqrt(reachable) / 0.8);
  if (next <= plan_.rays) {
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the estimated error is %.3g at %lld rays per "
                  "patch, the most allowed",
                  target, solved_.report.relativeStderr, static_cast<long long>(plan_.rays));
    console_.warn(text);
    return false;
  }
  // More rays grow F on the same patches: where it would no longer fit (--max-patches' model),
  // stop here and say so, rather than run out of memory in the round.
  if (request_.maxPatches <= 0 && patchesThatFitAt(next) < mesh_.patchCount) {
    std::snprintf(text, sizeof text,
                  "target error %.3g not reached: the estimated error is %.3g at %lld rays per "
                  "patch; F at %lld rays per patch would not fit %lld patches in half the "
                  "memory (use more nodes)",
                  target, solved_.report.relativeStderr, static_cast<long long>(plan_.rays),
                  static_cast<long long>(next), static_cast<long long>(mesh_.patchCount));
    console_.warn(text);
    return false;
  }
  std::snprintf(text, sizeof text,
                "target error: estimated %.3g > %.3g at %lld rays per patch (sampling %.3g, "
                "discretisation %.3g); going on with %lld rays per patch%s%s",
                solved_.report.relativeStderr, target, static_cast<long long>(plan_.rays), s, d,
                static_cast<long long>(next), d >= s ? " (refinement stopped: " : "",
                d >= s ? (refine + ")").c_str() : "");
  console_.info(text);
  if (!wellMeasured) measuredAgainAt_ = next;
  solved_.resume = SolveProgress{
      {1, 1, 1}, solved_.solution.radiosity, solved_.report.history};  // the rows stay
  plan_.rays = next;
  maxPatches_ = patchBound(next);
  return true;
}

// F for the solve, which lends its one store to PETSc. The rows of F as sampled are needed again
// for checkpoints, the next round and --save-formfactors: the solve hands the store back where M
// stays as made on it (F's values give the sums back: formfactor::appendRows), and the result's F
// is written from it; otherwise (F repaired, a solver that works on M in place) the store is
// kept here, and --save-formfactors keeps F's values for the result.
solve::FormFactorRows SolvePipeline::formFactorsToSolve() {
  const bool repaired = plan_.reciprocity || request_.dropThreshold > 0;
  const bool keepRows = !request_.checkpoint.empty() || request_.targetError > 0;
  if (formFactors_.balanceColumns && !repaired) return balancedFormFactors(keepRows);
  const solve::Solver solver = solved_.options.solver;
  const bool handBack = (keepRows || request_.saveFormFactors) && !repaired &&
                        solver != solve::Solver::kCg && solver != solve::Solver::kGaussSeidel;
  solved_.options.handBackRows = handBack;
  solved_.options.rowsBack = handBack ? &state_.rows.values : nullptr;
  formFactors_.storeHandedBack = handBack;
  if (request_.saveFormFactors && !repaired && !handBack)
    formFactors_.repaired = formfactor::toFormFactors(formFactors_.store);
  if (repaired) {
    if (keepRows) state_.rows.values = std::move(formFactors_.store);
    formFactors_.store = formfactor::SplitRows();
    return request_.saveFormFactors ? formFactors_.repaired : std::move(formFactors_.repaired);
  }
  if (keepRows && !handBack) state_.rows.values = formFactors_.store;
  return std::move(formFactors_.store);
}

}  // namespace radiosity::run
