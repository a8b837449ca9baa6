// The pilot of a cluster: each light weighted by Σ MIS weight × the mean emission of the patch
// reached, an estimate of how much light it sends the cluster. The pilot's own scrambles keep
// it apart from the rows' samples.
#include "formfactor/light_pilot.h"

#include <algorithm>

#include "formfactor/hemisphere_rays.h"
#include "formfactor/mis_weights.h"
#include "formfactor/sobol.h"

namespace radiosity::formfactor {

void LightPilot::traceHemisphereSamples(int64_t first, int64_t end, int64_t each, uint64_t seed,
                                        std::vector<std::pair<int64_t, double>>& seen) {
  for (int64_t p = first; p < end; ++p) {
    makeHemisphereRays(patches_,
                       {p, 0, each, seed, rayOffset(tracer_, p), trace::kPilotHemisphereScramble},
                       patchRays_, scratch_);
    const auto at = static_cast<size_t>((p - first) * each);
    for (size_t k = 0; k < static_cast<size_t>(each); ++k) {
      rays_.set(at + k, batchOrigin(patchRays_, k), batchDirection(patchRays_, k),
                patchRays_.tFar[k]);
      patch_[at + k] = p;
    }
  }
  tracer_.intersect(rays_, hits_);
  const size_t n = patch_.size();
  raysCast_ += static_cast<int64_t>(n);
  const LightChoice byArea(emitters_);
  for (size_t k = 0; k < n; ++k) {
    const int64_t j = hits_.patch[k];
    if (j < 0 || j == patch_[k] || !hits_.front[k] || !isEmitter(patches_, j)) continue;
    const Vec3 direction = batchDirection(rays_, k);
    const double ph = hemisphereDensity(direction, normals_[patch_[k]]);
    const double pe = emitterDensity(byArea, normals_, direction, j, hits_.distance[k]);
    seen.emplace_back(emitters_.lightOf(j), ph / (ph + pe) * meanEmission(patches_, j));
  }
}

// The emitter samples leave from the hemisphere samples' points (still in the batch).
void LightPilot::traceEmitterSamples(int64_t each, uint64_t seed,
                                     std::vector<std::pair<int64_t, double>>& seen) {
  const size_t n = patch_.size();
  const LightChoice byArea(emitters_);
  for (size_t k = 0; k < n; ++k) {
    const int64_t p = patch_[k];
    const auto seeds = scrambleSeeds(seed, p, trace::kPilotEmitterScramble);
    const auto u = scrambledSobol(owenScramble(static_cast<uint32_t>(k % each), seeds[3]), seeds);
    const EmitterSet::Sample light = emitters_.sample(u[0], u[1], u[2]);
    const Vec3 origin = batchOrigin(rays_, k), toward = light.point - origin;
    const double distance = length(toward);
    const Vec3 direction = (1.0 / distance) * toward;
    const double ph = hemisphereDensity(direction, normals_[p]);
    const double pe =
        light.patch == p ? 0.0 : emitterDensity(byArea, normals_, direction, light.patch, distance);
    const bool cast = ph > 0 && pe > 0;
    weight_[k] = cast ? ph / (ph + pe) * meanEmission(patches_, light.patch) : 0.0;
    target_[k] = cast ? light.patch : -1;
    rays_.set(k, origin, direction, cast ? distance * (1 - kShadowGap) : -1.0);
  }
  tracer_.intersect(rays_, hits_);
  for (size_t k = 0; k < n; ++k) {
    if (target_[k] < 0) continue;
    ++raysCast_;
    if (hits_.patch[k] < 0) seen.emplace_back(emitters_.lightOf(target_[k]), weight_[k]);
  }
}

LightChoice LightPilot::choose(int64_t first, int64_t end, uint64_t seed) {
  const int64_t each = (kLightPilotSamples + (end - first) - 1) / (end - first);
  const auto n = static_cast<size_t>(each * (end - first));
  rays_.resize(n);
  patch_.resize(n);
  target_.resize(n);
  weight_.resize(n);
  std::vector<std::pair<int64_t, double>> seen;
  traceHemisphereSamples(first, end, each, seed, seen);
  traceEmitterSamples(each, seed, seen);
  // Summed per light in a fixed order: the same choice whichever thread or rank makes it.
  std::stable_sort(seen.begin(), seen.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<int64_t, double>> weights;
  int64_t seenOnce = 0;  // lights one pilot sample alone reached
  for (size_t k = 0; k < seen.size(); ++k) {
    const int64_t light = seen[k].first;
    if (weights.empty() || weights.back().first != light) weights.emplace_back(light, 0.0);
    weights.back().second += seen[k].second;
    const bool firstOfLight = k == 0 || seen[k - 1].first != light;
    const bool lastOfLight = k + 1 == seen.size() || seen[k + 1].first != light;
    if (firstOfLight && lastOfLight) ++seenOnce;
  }
  const double unseen = seen.empty() ? 1.0 : double(seenOnce) / double(seen.size());
  return LightChoice(emitters_, weights, unseen);
}

}  // namespace radiosity::formfactor
