// The path tracer of verify/path_tracer.h: its own emitter table, warps and random numbers
// (Philox keyed by seed, patch and path); only the ray casts go through trace/'s tracer.
#include "verify/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "trace/counter_rng.h"
#include "trace/parallel_for.h"
#include "trace/trace.h"

namespace radiosity::verify {

namespace {

/// Mixed into the seed so that these streams are not those of any other use of the same seed.
constexpr uint64_t kStreamSalt = 0x7665726966792d31ull;  // "verify-1"

uint64_t mix64(uint64_t x) {  // splitmix64's finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Uniform point on the triangle (a, b, c) from two uniforms.
Vec3 uniformPoint(Vec3 a, Vec3 b, Vec3 c, double u1, double u2) {
  const double root = std::sqrt(u1);
  return (1 - root) * a + (root * (1 - u2)) * b + (root * u2) * c;
}

/// A cosine-weighted direction around the unit normal n (a uniform disk point lifted).
Vec3 cosineDirection(Vec3 n, double u1, double u2) {
  // Orthonormal basis around n (Frisvad's construction, made safe for n.z ≈ −1).
  Vec3 t, b;
  if (n.z < -0.9999999) {
    t = {0, -1, 0};
    b = {-1, 0, 0};
  } else {
    const double a = 1 / (1 + n.z), d = -n.x * n.y * a;
    t = {1 - n.x * n.x * a, d, -n.x};
    b = {d, 1 - n.y * n.y * a, -n.y};
  }
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  const double x = r * std::cos(phi), y = r * std::sin(phi);
  const double z = std::sqrt(std::max(0.0, 1 - u1));
  return x * t + y * b + z * n;
}

double largest(const Rgb& v) { return std::max({v[0], v[1], v[2]}); }

}  // namespace

struct PathTracer::Impl {
  Impl(const Mesh& m, int buildThreads, int64_t most)
      : mesh(m), tracer(m, buildThreads), maxBounces(most) {
    const int64_t n = mesh.triangleCount();
    normal.resize(n);
    for (int64_t t = 0; t < n; ++t) normal[t] = mesh.normal(t);
    // The emitters, picked with probability ∝ area × emitted power (summed over channels).
    for (int64_t t = 0; t < n; ++t) {
      const Rgb& e = mesh.emission[t];
      const double power = mesh.area(t) * (e[0] + e[1] + e[2]);
      if (!(power > 0)) continue;
      emitter.push_back(t);
      totalPower += power;
      cumulativePower.push_back(totalPower);
    }
  }

  const Mesh& mesh;
  trace::SceneTracer tracer;
  int64_t maxBounces;
  std::vector<Vec3> normal;
  std::vector<int64_t> emitter;
  std::vector<double> cumulativePower;  ///< running sums of area × (E_r + E_g + E_b)
  double totalPower = 0;

  /// The density per unit area with which nextEvent() picks a point of emitter e.
  double emitterPointDensity(int64_t e) const {
    const Rgb& emitted = mesh.emission[e];
    return (emitted[0] + emitted[1] + emitted[2]) / totalPower;
  }

  /// Light reaching x on `patch` (unit normal n) straight from one point y on one emitter, per
  /// channel, weighted against the bounce ray by the balance heuristic of multiple importance
  /// sampling: f / (p_light + p_bounce) in solid angle, f = E_y cos θ_x / π, p_light =
  /// density(y) r² / cos θ_y, p_bounce = cos θ_x / π. Bounded by E_y, so an emitter next to x
  /// (a corner, r → 0) does not give the 1/r² spikes of plain area sampling (whose variance is
  /// infinite at concave edges).
  Rgb nextEvent(int64_t patch, Vec3 x, Vec3 n, const std::array<double, 4>& u,
                int64_t& rays) const {
    if (emitter.empty()) return {0, 0, 0};
    const double target = u[0] * totalPower;
    const auto found = std::upper_bound(cumulativePower.begin(), cumulativePower.end(), target);
    const size_t k = std::min<size_t>(found - cumulativePower.begin(), emitter.size() - 1);
    const int64_t e = emitter[k];
    if (e == patch) return {0, 0, 0};  // a flat patch does not light itself
    const Vec3 y =
        uniformPoint(mesh.corner(e, 0), mesh.corner(e, 1), mesh.corner(e, 2), u[1], u[2]);
    const double offset = tracer.offset(patch);  // rays start this far off their surface
    const Vec3 origin = x + offset * n;
    const Vec3 toY = y - origin;
    const double distance2 = dot(toY, toY), distance = std::sqrt(distance2);
    const double gap = tracer.offset(e);  // and end this far short of the emitter's
    if (!(distance > offset + gap)) return {0, 0, 0};
    const Vec3 w = (1 / distance) * toY;
    const double cosX = dot(n, w), cosY = -dot(normal[e], w);
    if (cosX <= 0 || cosY <= 0) return {0, 0, 0};  // behind x, or the emitter's unlit side
    ++rays;
    // Anything in between, either side, shadows y; stop short of the emitter's own surface.
    if (tracer.intersect(origin, w, 0, distance - gap)) return {0, 0, 0};
    const double bounceDensity = cosX / std::numbers::pi;
    const double lightDensity = emitterPointDensity(e) * distance2 / cosY;
    const double weight = bounceDensity / (lightDensity + bounceDensity);  // f/(p+p) per unit E
    const Rgb& emitted = mesh.emission[e];
    return {emitted[0] * weight, emitted[1] * weight, emitted[2] * weight};
  }

  /// The share the bounce ray gets of the light of emitter j it hit at `distance` along
  /// `direction` from a surface of normal n (the other share is nextEvent()'s).
  double bounceWeight(int64_t j, Vec3 n, Vec3 direction, double distance) const {
    const double cosX = dot(n, direction), cosY = -dot(normal[j], direction);
    if (!(cosX > 0) || !(cosY > 0)) return 0;
    const double bounceDensity = cosX / std::numbers::pi;
    const double lightDensity = emitterPointDensity(j) * distance * distance / cosY;
    return bounceDensity / (lightDensity + bounceDensity);
  }

  /// One path's estimate of B_patch at a uniform point of the patch; adds its vertices to
  /// `bounces` and 1 to `capped` if it was cut at maxBounces.
  Rgb path(int64_t patch, uint64_t key, uint32_t index, int64_t& rays, int64_t& bounces,
           int64_t& capped) const {
    uint32_t stream = 0;
    auto uniforms = [&] {
      return trace::uniforms(key, static_cast<uint64_t>(patch), index, stream++);
    };
    const auto start = uniforms();
    Vec3 x = uniformPoint(mesh.corner(patch, 0), mesh.corner(patch, 1), mesh.corner(patch, 2),
                          start[0], start[1]);
    int64_t at = patch;
    Rgb gathered = {0, 0, 0}, throughput = {1, 1, 1};
    bool ended = false;
    for (int64_t vertex = 0; vertex < maxBounces; ++vertex) {
      ++bounces;
      ended = true;  // unless it goes on from this vertex
      const auto light = uniforms(), bounce = uniforms();
      const Vec3 n = normal[at];
      const Rgb direct = nextEvent(at, x, n, light, rays);
      for (int c = 0; c < 3; ++c) gathered[c] += throughput[c] * direct[c];
      // The bounce: cosine-weighted, so the path goes on with weight ρ of what it hits.
      const Vec3 direction = cosineDirection(n, bounce[0], bounce[1]);
      ++rays;
      const auto hit = tracer.intersect(x + tracer.offset(at) * n, direction, 0);
      if (!hit || hit->patch == at) break;                   // escaped; never itself
      if (dot(direction, hit->geometricNormal) >= 0) break;  // the back of a face absorbs
      const int64_t j = hit->patch;
      // The bounce's share of j's own light (cosine-weighted: its estimate is E_j itself).
      const Rgb& emitted = mesh.emission[j];
      if (emitted[0] > 0 || emitted[1] > 0 || emitted[2] > 0) {
        const double weight = bounceWeight(j, n, direction, hit->distance);
        for (int c = 0; c < 3; ++c) gathered[c] += throughput[c] * weight * emitted[c];
      }
      const Rgb& rho = mesh.reflectance[j];
      // Russian roulette with survival max_c ρ_c: the largest channel's throughput stays put,
      // so ρ²/q ≤ ρ < 1 per bounce and the variance stays finite for any ρ < 1.
      const double survive = largest(rho);
      if (!(survive > 0) || bounce[2] >= survive) break;
      for (int c = 0; c < 3; ++c) throughput[c] *= rho[c] / survive;
      const double u = hit->u, v = hit->v;
      x = (1 - u - v) * mesh.corner(j, 0) + u * mesh.corner(j, 1) + v * mesh.corner(j, 2);
      at = j;
      ended = false;
    }
    if (!ended) ++capped;  // survived every bounce: cut at the cap, its light beyond is lost
    const Rgb& e = mesh.emission[patch];
    const Rgb& rho = mesh.reflectance[patch];
    return {e[0] + rho[0] * gathered[0], e[1] + rho[1] * gathered[1], e[2] + rho[2] * gathered[2]};
  }
};

PathTracer::PathTracer(const Mesh& mesh, int buildThreads, int64_t maxBounces) {
  if (maxBounces < 1 || maxBounces > kMostBounces)
    throw std::invalid_argument("PathTracer: maxBounces must be in [1, 2^20]");
  impl_ = std::make_unique<Impl>(mesh, buildThreads, maxBounces);
}

PathTracer::~PathTracer() = default;

PatchReference PathTracer::trace(int64_t patch, int64_t paths, uint64_t seed) const {
  if (patch < 0 || patch >= impl_->mesh.triangleCount())
    throw std::out_of_range("PathTracer::trace: no patch " + std::to_string(patch));
  if (paths < 2 || paths > (int64_t{1} << 32))
    throw std::invalid_argument("PathTracer::trace: paths must be in [2, 2^32]");
  const uint64_t key = mix64(seed ^ kStreamSalt);
  PatchReference reference;
  reference.paths = paths;
  // Welford's running mean and sum of squared deviations, in path order (deterministic).
  Rgb mean = {0, 0, 0}, squares = {0, 0, 0};
  for (int64_t p = 0; p < paths; ++p) {
    const Rgb b = impl_->path(patch, key, static_cast<uint32_t>(p), reference.rays,
                              reference.bounces, reference.capped);
    const double count = static_cast<double>(p + 1);
    for (int c = 0; c < 3; ++c) {
      const double delta = b[c] - mean[c];
      mean[c] += delta / count;
      squares[c] += delta * (b[c] - mean[c]);
    }
  }
  const double n = static_cast<double>(paths);
  for (int c = 0; c < 3; ++c) {
    reference.radiosity[c] = mean[c];
    reference.standardError[c] = std::sqrt(std::max(0.0, squares[c]) / (n - 1) / n);
  }
  return reference;
}

std::vector<PatchReference> PathTracer::trace(
    const std::vector<int64_t>& patches, int64_t paths, uint64_t seed, int threads,
    const std::function<void(int64_t patchesDone)>& progress) const {
  std::vector<PatchReference> answer(patches.size());
  std::atomic<int64_t> done{0};
  const auto count = static_cast<int64_t>(patches.size());
  trace::parallelFor(count, threads, [&](int64_t begin, int64_t end, int slot) {
    for (int64_t k = begin; k < end; ++k) {
      answer[k] = trace(patches[k], paths, seed);
      const int64_t finished = done.fetch_add(1) + 1;
      if (slot == 0 && progress) progress(finished);
    }
  });
  return answer;
}

}  // namespace radiosity::verify
