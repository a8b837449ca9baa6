#include "solve/direct_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "formfactor/emitter_set.h"
#include "solve/owned_patch_rays.h"
#include "trace/counter_rng.h"

namespace radiosity::solve {

namespace {

constexpr uint32_t kDirectSlopeStream = 0xd15d;

// Shadow rays stop this share of the distance short of the light's point (as the form factors'
// emitter rays do).
constexpr double kShadowGap = 1e-4;

// The direct light inside one patch, from its own samples: the mean irradiance from the emitters
// and its least-squares slope across the patch, per channel. A shadow edge that crosses the patch
// shows in the slope (its first moment, which is what a gather from elsewhere weighs it by),
// where the neighbours' means smear it over three patches. The slope is kept only where some of
// the shadow rays were blocked and some not (a sixteenth each): where every sample sees the
// light, the direct light's variation inside a patch is smooth and the indirect light's partly
// undoes it (in a closed emitting box B is uniform while the direct part is not).
struct DirectLight {
  Rgb mean{0, 0, 0};
  std::array<Vec3, 3> slope{};
};

// The mean of the samples' direct light (`weight` at `point`, weight 0 where shadowed) and its
// least-squares slope in the patch's plane about the points' mean.
void fitDirectLight(const std::vector<Vec3>& point, const std::vector<Rgb>& weight,
                    const trace::PatchFrame& frame, DirectLight& mine) {
  const auto samples = static_cast<int64_t>(point.size());
  Vec3 centre{0, 0, 0};
  for (const Vec3& p : point) centre = centre + p;
  centre = (1.0 / static_cast<double>(samples)) * centre;
  double a11 = 0, a12 = 0, a22 = 0;
  std::array<std::array<double, 2>, 3> rhs{};
  for (int64_t k = 0; k < samples; ++k) {
    const Vec3 d = point[k] - centre;
    const double x = dot(d, frame.tangent), y = dot(d, frame.bitangent);
    a11 += x * x, a12 += x * y, a22 += y * y;
    for (int c = 0; c < 3; ++c) {
      mine.mean[c] += weight[k][c] / static_cast<double>(samples);
      rhs[c][0] += x * weight[k][c], rhs[c][1] += y * weight[k][c];
    }
  }
  const double det = a11 * a22 - a12 * a12;
  if (!(det > 1e-12 * (a11 + a22) * (a11 + a22))) return;
  for (int c = 0; c < 3; ++c) {
    const double gx = (a22 * rhs[c][0] - a12 * rhs[c][1]) / det,
                 gy = (a11 * rhs[c][1] - a12 * rhs[c][0]) / det;
    if (std::isfinite(gx) && std::isfinite(gy))
      mine.slope[c] = gx * frame.tangent + gy * frame.bitangent;
  }
}

}  // namespace

DirectParts directLight(const trace::SceneTracer& tracer, const Mesh& patches,
                        partition::PatchRange owned, uint64_t seed, int64_t samples, int threads) {
  DirectParts out{std::vector<Rgb>(owned.size(), Rgb{0, 0, 0}), {}};
  const formfactor::EmitterSet emitters(patches);
  if (emitters.empty()) return out;
  std::vector<decltype(out.edgeSlope)> edgeSlopes(static_cast<size_t>(std::max(threads, 1)));
  struct Samples {  // of the row a thread is on
    std::vector<Vec3> point;
    std::vector<Rgb> weight;
  };
  std::vector<Samples> slots(static_cast<size_t>(std::max(threads, 1)),
                             Samples{std::vector<Vec3>(samples), std::vector<Rgb>(samples)});
  auto aim = [&](int64_t i, const trace::PatchFrame& frame, double offset,
                 trace::SceneTracer::RayBatch& rays, int slot) {
    auto& [point, weight] = slots[slot];
    for (int64_t k = 0; k < samples; ++k) {
      const auto u = trace::uniforms(seed, static_cast<uint64_t>(i), static_cast<uint32_t>(k),
                                     kDirectSlopeStream);
      // Stratified along the samples (k + u)/n in the first dimension: the slope's noise is
      // that of the light, not of where the points fell.
      const double across = (static_cast<double>(k) + u[0]) / static_cast<double>(samples);
      point[k] = trace::pointOnTriangle(frame.v0, frame.v1, frame.v2, across, u[1]);
      const auto light =
          emitters.sample(u[2], u[3],
                          trace::uniforms(seed, static_cast<uint64_t>(i), static_cast<uint32_t>(k),
                                          kDirectSlopeStream + 1)[0]);
      const Vec3 origin = point[k] + offset * frame.normal, toward = light.point - origin;
      const double distance = length(toward);
      const Vec3 direction = (1 / distance) * toward;
      const double cosHere = dot(direction, frame.normal), cosThere = -dot(direction, light.normal);
      const bool cast = light.patch != i && cosHere > 0 && cosThere > 0 && distance > 0;
      const double g = cast ? cosHere * cosThere * emitters.totalArea() /
                                  (std::numbers::pi * distance * distance)
                            : 0.0;
      for (int c = 0; c < 3; ++c) weight[k][c] = g * patches.emission[light.patch][c];
      rays.set(k, origin, cast ? direction : frame.normal,
               cast ? distance * (1 - kShadowGap) : -1.0);
    }
  };
  auto score = [&](int64_t i, const trace::PatchFrame& frame,
                   const trace::SceneTracer::RayBatch& rays,
                   const trace::SceneTracer::HitBatch& hits, int slot) {
    auto& [point, weight] = slots[slot];
    int64_t blocked = 0, seen = 0;
    for (int64_t k = 0; k < samples; ++k) {
      if (!(rays.tFar[k] > 0)) continue;  // not cast
      if (hits.patch[k] >= 0) {
        weight[k] = Rgb{0, 0, 0};
        ++blocked;
      } else {
        ++seen;
      }
    }
    // A sixteenth at least each way: a grazing ray now and then met in float along a crease is
    // no shadow.
    const int64_t least = std::max<int64_t>(2, (blocked + seen) / 16);
    DirectLight light;
    fitDirectLight(point, weight, frame, light);
    out.mean[i - owned.begin] = light.mean;
    if (blocked >= least && seen >= least)
      edgeSlopes[slot].emplace_back(i - owned.begin, light.slope);
  };
  traceOwnedPatches(tracer, patches, owned, samples, threads, aim, score);
  for (auto& slopes : edgeSlopes) {
    out.edgeSlope.insert(out.edgeSlope.end(), slopes.begin(), slopes.end());
    slopes = {};
  }
  std::sort(out.edgeSlope.begin(), out.edgeSlope.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

}  // namespace radiosity::solve
