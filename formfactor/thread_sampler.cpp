// Rows of F by Monte Carlo. Hemisphere sampling: the share of cosine-distributed rays from
// patch i whose first hit is the front of patch j estimates F_ij without bias (the cosines and
// 1/(π r²) of the kernel cancel against the sampling density), a row has at most N entries, and
// in a closed scene it sums to exactly 1. Emitter MIS adds, per sample, a point uniform on the
// emitters' total area with a shadow ray; with the balance heuristic each of the two samples
// contributes p_h / (p_h + p_e) to the patch it reaches (p_h, p_e: the two densities of that
// direction in solid angle), which is at most 1 and unbiased.
#include "formfactor/thread_sampler.h"

#include <algorithm>
#include <cmath>

#include "formfactor/hemisphere_rays.h"
#include "formfactor/mis_weights.h"
#include "formfactor/sobol.h"

namespace radiosity::formfactor {

namespace {

constexpr double kFixedPointOne = 0x1p32;  // contributions are summed in units of 2^-32

constexpr int64_t kOne = int64_t{1} << 32;  // a whole sample's contribution

}  // namespace

ThreadSampler::ThreadSampler(const SceneTracer& tracer, const Mesh& patches,
                             const std::vector<Vec3>& normals, const Options& options,
                             const EmitterSet& emitters, const ExactRows* exact)
    : tracer_(tracer),
      exact_(exact),
      patches_(patches),
      normals_(normals),
      options_(options),
      mis_(options.estimator == Estimator::kEmitterMis && !emitters.empty()) {
  if (patches.hasLabels()) statistics_.backFaceHitsByLabel.assign(patches.labelNames.size(), 0);
  setSamples(options.firstSample, options.raysPerPatch);
}

void ThreadSampler::sampleRow(int64_t i, const LightChoice& lights, std::vector<int64_t>& columns,
                              std::vector<int64_t>& sums) {
  if (exact_) {
    const ExactRows::Appended row = exact_->appendRow(i, options_.raysPerPatch, columns, sums);
    statistics_.pairFactors += row.pairFactors;
    statistics_.rowsOffTheirSum += row.offItsSum ? 1 : 0;
    return;
  }
  lights_ = &lights;
  makeHemisphereRays(
      patches_,
      {i, options_.firstSample, options_.raysPerPatch, options_.seed, rayOffset(tracer_, i)}, rays_,
      scratch_);
  tracer_.intersect(rays_, hits_);
  scoreHemisphereRays(i, normals_[i]);
  if (mis_) {
    makeEmitterRays(i, normals_[i]);
    tracer_.intersect(rays_, hits_);
    scoreEmitterRays();
  }
  if (sortHits_) return appendPairs(columns, sums);
  appendAccumulated(columns, sums);
}

Statistics ThreadSampler::takeStatistics() {
  Statistics taken = statistics_;
  statistics_ = Statistics();
  if (patches_.hasLabels())
    statistics_.backFaceHitsByLabel.assign(taken.backFaceHitsByLabel.size(), 0);
  return taken;
}

void ThreadSampler::setSamples(int64_t firstSample, int64_t count) {
  options_.firstSample = firstSample;
  options_.raysPerPatch = count;
  rays_.resize(count);
  const int64_t n = patches_.triangleCount();
  sortHits_ = (count <= kFewHits && n >= kLargeScene) || n > kDenseMaxPatches;
  // The dense accumulator only where it is used: 8 bytes per patch and thread.
  if (!sortHits_ && accumulator_.empty()) accumulator_.assign(n, 0);
}

bool ThreadSampler::seesOnlyBacks(int64_t i) const {
  for (size_t k = 0; k < rays_.size(); ++k)
    if (hits_.patch[k] < 0 || (hits_.patch[k] != i && hits_.front[k])) return false;
  return !rays_.tFar.empty();
}

void ThreadSampler::scoreHemisphereRays(int64_t i, Vec3 normal) {
  statistics_.raysCast += static_cast<int64_t>(rays_.size());
  if (seesOnlyBacks(i)) {  // a hidden patch's row, or one inside a model wound inside out
    statistics_.backFaceHits += static_cast<int64_t>(rays_.size());
    statistics_.blindBackFaceHits += static_cast<int64_t>(rays_.size());
    if (patches_.hasLabels())
      for (size_t k = 0; k < rays_.size(); ++k)
        ++statistics_.backFaceHitsByLabel[patches_.label[hits_.patch[k]]];
    return;
  }
  for (size_t k = 0; k < rays_.size(); ++k) {
    const int64_t j = hits_.patch[k];
    if (j < 0) {
      ++statistics_.escapedRays;
    } else if (j == i || !hits_.front[k]) {
      ++statistics_.backFaceHits;  // absorbed: the back of a one-sided patch
      if (patches_.hasLabels()) ++statistics_.backFaceHitsByLabel[patches_.label[j]];
    } else if (mis_ && isEmitter(patches_, j)) {
      const Vec3 direction = batchDirection(rays_, k);
      const double ph = hemisphereDensity(direction, normal);
      add(j, ph / (ph + emitterDensity(*lights_, normals_, direction, j, hits_.distance[k])));
    } else {
      add(j, kOne);
    }
  }
}

// The emitter sample of sample k leaves from the same point as its hemisphere ray (still in
// the batch) and draws the same dimensions at a shuffled index (Burley's padding): sharing
// the index would tie the light point to the receiver point for good.
void ThreadSampler::makeEmitterRays(int64_t i, Vec3 normal) {
  const auto seeds = scrambleSeeds(options_.seed, i, trace::kEmitterScramble);
  emitterTarget_.assign(rays_.size(), -1);
  emitterWeight_.assign(rays_.size(), 0.0);
  for (size_t k = 0; k < rays_.size(); ++k) {
    const auto index = static_cast<uint32_t>(options_.firstSample + static_cast<int64_t>(k));
    const auto u = scrambledSobol(owenScramble(index, seeds[3]), seeds);
    const EmitterSet::Sample light = lights_->sample(u[0], u[1], u[2]);
    const Vec3 origin = batchOrigin(rays_, k), toward = light.point - origin;
    const double distance = length(toward);
    const Vec3 direction = (1.0 / distance) * toward;
    const double ph = hemisphereDensity(direction, normal);
    const double pe = light.patch == i
                          ? 0.0
                          : emitterDensity(*lights_, normals_, direction, light.patch, distance);
    if (ph > 0 && pe > 0) {  // else the emitter faces away or lies behind: no ray
      emitterTarget_[k] = light.patch;
      emitterWeight_[k] = ph / (ph + pe);
    }
    rays_.set(k, origin, direction, emitterTarget_[k] >= 0 ? distance * (1 - kShadowGap) : -1.0);
  }
}

void ThreadSampler::scoreEmitterRays() {
  for (size_t k = 0; k < rays_.size(); ++k) {
    if (emitterTarget_[k] < 0) continue;
    ++statistics_.raysCast;
    // Visible when nothing lies between the origin and the sampled point.
    if (hits_.patch[k] < 0) add(emitterTarget_[k], emitterWeight_[k]);
  }
}

void ThreadSampler::add(int64_t column, int64_t amount) {
  if (amount == 0) return;
  if (sortHits_) {
    pairs_.push_back({column, amount});
  } else {
    if (accumulator_[column] == 0) touched_.push_back(column);
    accumulator_[column] += amount;
  }
}

void ThreadSampler::add(int64_t column, double amount) {
  add(column, static_cast<int64_t>(std::llround(amount * kFixedPointOne)));
}

// In column order: a sort of the touched columns, or, when they are many, one pass over the
// accumulator (cheaper than sorting a row that touches a good share of the patches).
void ThreadSampler::appendAccumulated(std::vector<int64_t>& columns, std::vector<int64_t>& sums) {
  const auto n = static_cast<int64_t>(accumulator_.size());
  const auto touched = static_cast<int64_t>(touched_.size());
  if (touched * 16 >= n) {
    for (int64_t column = 0; column < n; ++column) {
      if (accumulator_[column] == 0) continue;
      columns.push_back(column);
      sums.push_back(accumulator_[column]);
      accumulator_[column] = 0;
    }
  } else {
    std::sort(touched_.begin(), touched_.end());
    for (int64_t column : touched_) {
      columns.push_back(column);
      sums.push_back(accumulator_[column]);
      accumulator_[column] = 0;
    }
  }
  touched_.clear();
}

// A row of few samples: its hits sorted by column and summed, with no access to the dense
// accumulator, whose one int64 per patch (8 MB at 10^6 patches, per thread) costs a cache miss
// per hit once the scene is large. The sums are integers: the same in any order.
void ThreadSampler::appendPairs(std::vector<int64_t>& columns, std::vector<int64_t>& sums) {
  std::sort(pairs_.begin(), pairs_.end(),
            [](const Hit& a, const Hit& b) { return a.column < b.column; });
  for (size_t k = 0; k < pairs_.size(); ++k) {
    if (k == 0 || pairs_[k].column != pairs_[k - 1].column) {
      columns.push_back(pairs_[k].column);
      sums.push_back(0);
    }
    sums.back() += pairs_[k].amount;
  }
  pairs_.clear();
}

}  // namespace radiosity::formfactor
