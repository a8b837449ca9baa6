// verify: a path-traced reference for a solved result (used by `radiosity verify`). For a patch
// i it estimates the patch-averaged radiosity B_i = E_i + ρ_i H_i of the continuous problem
// (no patch-constant approximation): a uniform point x on the patch, then the irradiance H(x)
// by a path: at each vertex a point on an emitter (picked by area × power) and a
// cosine-weighted bounce, their two estimates of the direct light combined by multiple
// importance sampling (balance heuristic), the path going on with weight ρ of what the bounce
// hit, ended by Russian roulette, or cut at a cap on its length (its light beyond is lost).
// It is independent of the solver by construction: it uses only the mesh (geometry, ρ, E) and
// ray casts through the Embree tracer, never the form factors, the solver's sampling
// sequences or its emitter table, so agreement with the solver's B is evidence, not a
// tautology. Its random numbers are keyed by (seed, patch, path), so a patch's estimate is the
// same on any number of ranks and threads.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/mesh.h"

namespace radiosity::verify {

/// The default cap on a path's bounces: ρ ≤ 0.99 paths reach it with probability ≤ e^-100,
/// so it cuts nothing in ordinary scenes; at ρ = 1 (a closed region) paths end only there.
inline constexpr int64_t kDefaultMaxBounces = 10000;
/// The largest cap accepted (a path that long takes about a second).
inline constexpr int64_t kMostBounces = int64_t{1} << 20;

/// The path-traced B of one patch, per channel: the mean of `paths` independent estimates and
/// its standard error (their sample standard deviation / √paths).
struct PatchReference {
  Rgb radiosity{0, 0, 0};
  Rgb standardError{0, 0, 0};
  int64_t paths = 0;
  int64_t rays = 0;     ///< rays cast (bounces and shadow rays)
  int64_t bounces = 0;  ///< path vertices, summed over the paths (their mean length × paths)
  int64_t capped = 0;   ///< paths cut at the cap on bounces: their light beyond it is missing
};

class PathTracer {
 public:
  /// Builds the BVH over `mesh` (with at most `buildThreads` threads, 0: all cores) and the
  /// table of emitters (picked by area × emitted power). Keeps a reference to `mesh`, which
  /// must outlive the tracer. A path is cut after `maxBounces` bounces (in [1, kMostBounces]):
  /// the light it would have gathered beyond is missing, so the estimate is low where paths
  /// reach the cap (only where ρ is near 1: see kDefaultMaxBounces); they are counted.
  explicit PathTracer(const Mesh& mesh, int buildThreads = 0,
                      int64_t maxBounces = kDefaultMaxBounces);
  ~PathTracer();
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  /// B of `patch` from `paths` paths (≥ 2). Thread-safe. A hit on the back of a face absorbs
  /// the path (as in the solver), an escaping ray ends it; the survival probability of a
  /// bounce on patch j is max_c ρ_j,c, so the estimate is unbiased with finite variance for
  /// any ρ < 1 (paths then last about 1/(1 − ρ) bounces) up to the cap on bounces.
  PatchReference trace(int64_t patch, int64_t paths, uint64_t seed) const;

  /// trace() of each patch of `patches`, on `threads` threads sharing the patches; the answer
  /// is in the order of `patches` and does not depend on `threads`. `progress` (called from
  /// the calling thread, after one of its patches) gets the patches and paths finished so far.
  std::vector<PatchReference> trace(
      const std::vector<int64_t>& patches, int64_t paths, uint64_t seed, int threads,
      const std::function<void(int64_t patchesDone)>& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;  ///< owned
};

}  // namespace radiosity::verify
