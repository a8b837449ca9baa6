// Adaptive refinement rounds of `radiosity solve` (run/solve_pipeline.h): after a solve, the
// patches whose variation puts the most estimated error into the light the others gather are
// split (conforming), bisections where the light is flat are undone, the mesh is laid out again,
// every row is sampled afresh on the new mesh and the solve starts from the last B, each child
// taking its parent's and each merged patch the mean of its halves'.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "parallel/gather_all.h"
#include "run/derived_settings.h"
#include "run/memory_check.h"
#include "run/solve_pipeline.h"
#include "run/test_hooks.h"

namespace radiosity::run {

namespace {

// Each round splits the patches that hold this share of the estimated error (bulk marking):
// enough that a round pays for sampling the mesh again, few enough that the patches go where
// the error is.
constexpr double kRefineShare = 0.5;
// And at least this share of the patches: every row is sampled again each round, so a round
// that splits a few patches costs as much as one that splits many, and where half the error
// sits in a few patches along contact lines (the kernel is singular there, so quartering them
// takes little of it away) rounds of those alone stall (docs/notebook/scaling-measurements.md,
// "Adaptive meshes, run by run").
constexpr double kLeastShareMarked = 0.05;
// A marked patch is bisected twice (quartered), halving its size both ways: the error of its
// variation falls about fourfold where B is smooth, and a shadow edge across it is pinned to a
// quarter of the area.
constexpr int kRefineLevels = 2;
// A quartered patch adds three, and its closure (the neighbours across the split edges) about as
// many again.
constexpr int64_t kPatchesPerMark = 6;
// Each round also undoes the bisections where the light is flattest: every row is sampled again
// each round, so a patch that carries no error costs as much as one that does. Those whose halves
// hold the least estimated error, up to kMergeShare / kMergeGrowth of the whole: a pair merged
// back has about twice its halves' error where B is smooth (a patch's error from taking B
// constant grows as its size times its area), so counted kMergeGrowth times, for B that is not,
// the merged patches carry at most kMergeShare of the error before the round. A fifth instead
// merged twice as many on examples/office.obj, and its measured error rose by a tenth, which
// the estimate did not see (docs/scaling.md, "Coarsening").
constexpr double kMergeShare = 0.05;
constexpr double kMergeGrowth = 4;

}  // namespace

// The mesh in the user's coordinates (mesh_.patches before layOut, or with mesh_.worldVertices put
// back) refined at `marks` within `budget` patches, the round recorded; per new patch, the patch it
// lies in.
std::vector<int64_t> SolvePipeline::refineMesh(const std::vector<int64_t>& marks, int64_t budget) {
  std::vector<int64_t> parentOf;
  mesh_.patches = partition::refineMarked(mesh_.patches, marks, kRefineLevels, budget, &parentOf);
  state_.refinement.add(marks, mesh_.patches.triangleCount(), plan_.rays,
                        solved_.report.discretisationShare);
  return parentOf;
}

// The bisections of the refined mesh to undo, where the light is flat: of those whose halves
// this round left whole (`parentOf`: per refined patch, its patch before the round), alike in
// whether they see anything, the least error first (`sourceError`, per patch before the round)
// within kMergeShare of the error (the halves' error counted kMergeGrowth times).
std::vector<int64_t> SolvePipeline::flatBisections(const std::vector<int64_t>& parentOf,
                                                   const std::vector<int64_t>& sourceError) const {
  std::vector<int64_t> children(sourceError.size(), 0);
  for (int64_t p : parentOf) ++children[p];
  const int64_t n = mesh_.patches.triangleCount();
  std::vector<char> mergeable(n);
  std::vector<int64_t> error(n);
  for (int64_t t = 0; t < n; ++t) {
    mergeable[t] = children[parentOf[t]] == 1;
    error[t] = sourceError[parentOf[t]];
  }
  std::vector<partition::Bisection> candidates = partition::undoableBisections(mesh_.patches);
  std::erase_if(candidates, [&](const partition::Bisection& b) {
    for (int64_t t : b.halves)
      if (t >= 0 && mesh_.hidden[parentOf[t]] != mesh_.hidden[parentOf[b.halves[0]]]) return true;
    return false;
  });
  long double total = 0;
  for (int64_t e : sourceError) total += static_cast<long double>(e);
  return partition::markFlatBisections(candidates, error, mergeable,
                                       static_cast<double>(kMergeShare * total / kMergeGrowth));
}

// The refined mesh with the bisections at `vertices` undone, recorded with the round; per
// patch, the refined patches it is made of (the second -1: one).
std::vector<std::array<int64_t, 2>> SolvePipeline::mergeMesh(const std::vector<int64_t>& vertices) {
  std::vector<std::array<int64_t, 2>> halvesOf;
  mesh_.patches = partition::undoBisections(mesh_.patches, vertices, &halvesOf);
  state_.refinement.addMerges(vertices);
  return halvesOf;
}

// The most patches refinement may make at `rays` per patch: --max-patches, or as many as F fits
// in half the memory at the nonzeros per row of the last round sampled, grown in proportion to
// the rays and a quarter more for the finer mesh (they grow more slowly with the rays, and
// towards the rays with the patches), at most the rays' nonzeros; before any round, the rays'.
int64_t SolvePipeline::patchBound(int64_t rays) const {
  if (request_.maxPatches > 0) return request_.maxPatches;
  const int64_t fits = patchesThatFitAt(rays);
  if (boundByExactRows())
    return std::max(mesh_.patchCount, std::min(fits, formfactor::exactRowsPatchBound(rays)));
  return std::max(mesh_.patchCount, fits);
}

// The default round keeps exact rows exact: past their bound the rows would be sampled, with a
// sampling error far above the discretisation error the round takes away (the closed cube of
// 19,200 patches with one emitting square: 0.033 estimated with exact rows, 0.10 after a round
// past the bound). Rounds the user asks for (--refine-rounds N, --target-error) may go past it.
bool SolvePipeline::boundByExactRows() const {
  return request_.maxPatches <= 0 && plan_.exactRows && request_.targetError <= 0 &&
         request_.refineRounds < 0;
}

// How many patches F fits in half the memory at `rays` per patch (patchBound's model).
int64_t SolvePipeline::patchesThatFitAt(int64_t rays) const {
  const int64_t raysPerSample = formfactor::raysPerSample(*plan_.estimator);
  double columns = static_cast<double>(rays * raysPerSample);
  if (formFactors_.nonzerosPerRow > 0 && formFactors_.rays > 0 && !plan_.exactRows)
    columns = std::min(columns, 1.25 * formFactors_.nonzerosPerRow * static_cast<double>(rays) /
                                    static_cast<double>(formFactors_.rays));
  RunPlan atRays = plan_;  // (F's values in single precision at these rays, or not)
  atRays.rays = rays;
  return patchesThatFit(comm_, static_cast<int64_t>(std::ceil(columns)),
                        storesSinglePrecision(request_, atRays, mesh_.patches)
                            ? kBytesPerSingleNonzero
                            : kBytesPerNonzero);
}

// (room for a marked patch's split and its closure: the bound is passed by that at most)
bool SolvePipeline::roomToRefine() const {
  return maxPatches_ - mesh_.patchCount >= kPatchesPerMark;
}

// One refinement round, if any patch is worth splitting within --max-patches: the mesh refined
// and laid out again, the next solve set to start from this one's B. False: nothing to split.
bool SolvePipeline::refineRound(const std::string& why) {
  return refineRound(why, plan_, maxPatches_);
}

// (with the round's plan, whose rays may be more than this one's, and the patch bound at them:
// both the run's once the round goes ahead)
bool SolvePipeline::refineRound(const std::string& why, const RunPlan& next, int64_t bound) {
  const int64_t room = bound - mesh_.patchCount;
  if (room < kPatchesPerMark || solved_.discretisation.sourceError.empty()) return false;
  const std::vector<int64_t> marks = partition::markLargestErrors(
      solved_.discretisation.sourceError, kRefineShare,
      std::max<int64_t>(1, room / kPatchesPerMark),
      static_cast<int64_t>(kLeastShareMarked * static_cast<double>(mesh_.patchCount)));
  if (marks.empty()) return false;
  plan_ = next;
  maxPatches_ = bound;
  const std::vector<int64_t> sourceError = std::move(solved_.discretisation.sourceError);
  solved_.discretisation.sourceError = {};
  const std::vector<Rgb> previous = gatherAll(comm_, solved_.solution.radiosity, mesh_.patchCount);
  const int64_t before = mesh_.patchCount;
  tracer_.reset();
  state_.mesh = {};  // (views of the arrays the round replaces; layOut gives the new ones)
  mesh_.patches.vertices = mesh_.worldVertices;
  const std::vector<int64_t> parentOf = refineMesh(marks, maxPatches_);
  const int64_t refined = mesh_.patches.triangleCount();
  const std::vector<int64_t> merges = flatBisections(parentOf, sourceError);
  const std::vector<std::array<int64_t, 2>> halvesOf = mergeMesh(merges);
  layOut();
  std::vector<Rgb> start(mesh_.owned.size());
  for (int64_t i = mesh_.owned.begin; i < mesh_.owned.end; ++i) {
    const auto [first, second] = halvesOf[i];  // (halves of equal area: the midpoint's)
    Rgb& b = start[i - mesh_.owned.begin];
    b = previous[parentOf[first]];
    if (second >= 0)
      for (int c = 0; c < 3; ++c) b[c] = 0.5 * (b[c] + previous[parentOf[second]][c]);
  }
  solved_.resume = SolveProgress{{1, 1, 1}, std::move(start), solved_.report.history};
  state_.rows = SampledRows();  // every row afresh: the columns and the light choices changed
  state_.rowBalance.clear();
  char merged[200] = "";
  if (!merges.empty())
    std::snprintf(merged, sizeof merged,
                  ", and merged %lld pairs of halves back where the light is flat, -> %lld",
                  static_cast<long long>(refined - mesh_.patchCount),
                  static_cast<long long>(mesh_.patchCount));
  char text[900];
  std::snprintf(text, sizeof text,
                "refinement round %d (%s): split the %lld patches that hold half the estimated "
                "discretisation error, %lld -> %lld patches%s; sampling the rows again",
                state_.refinement.rounds(), why.c_str(), static_cast<long long>(marks.size()),
                static_cast<long long>(before), static_cast<long long>(refined), merged);
  console_.info(text);
  stallForTests("refine");
  return true;
}

// --refine-rounds auto: one round when the first solve's estimated error is mostly the mesh's.
bool SolvePipeline::refineByDefault() {
  const double d = solved_.report.discretisationShare, s = solved_.report.samplingShare;
  if (state_.refinement.rounds() > 0 || d <= kAutoRefineAbove || d <= kAutoRefineOver * s)
    return false;
  // (a round that samples every row again for less than the least share of the patches)
  if (boundByExactRows() &&
      maxPatches_ - mesh_.patchCount < kLeastShareMarked * static_cast<double>(mesh_.patchCount)) {
    console_.info("no refinement round by default: the rows are exact, and past " +
                  std::to_string(maxPatches_) +
                  " patches they would be sampled (--max-patches sets another bound)");
    return false;
  }
  char why[300];
  std::snprintf(why, sizeof why,
                "by default, as the estimated error is mostly the mesh's: discretisation %.3g, "
                "sampling %.3g; --refine-rounds 0 keeps the first mesh, --target-error goes on to "
                "a target, within at most %lld patches",
                d, s, static_cast<long long>(maxPatches_));
  return refineRound(why);
}

// A refinement round of --target-error. Every row is sampled again on the new mesh, so where the
// sampling error is above its share of the target too (0.8 × target / √2, the two parts alike),
// the round takes more rays as well, as a rays round would, for the cost of the rays alone. Not
// below half the discretisation error, though: rays cannot take that away, and a target far
// below it (1e-5 on a coarse room) multiplied the rays by 16 a round for nothing.
bool SolvePipeline::refineTowards(const std::string& why) {
  const double share =
      std::max(request_.targetError / std::sqrt(2.0), 0.5 * solved_.report.discretisationShare);
  RunPlan more = plan_;
  if (!plan_.exactRows && solved_.report.samplingShare > 0.8 * share)
    more.rays = nextRayCount(plan_.rays, solved_.report.samplingShare, share);
  if (more.rays == plan_.rays) return refineRound(why);
  const std::string what = why + "; and " + std::to_string(more.rays) +
                           " rays per patch, the sampling error being above its share too";
  if (refineRound(what, more, patchBound(more.rays))) return true;  // F grows with the rays
  // The larger part is the mesh's: where more rays leave no room under --max-patches, refine at
  // the rays as they are (more rays can come in a later round).
  return refineRound(why);
}

}  // namespace radiosity::run
