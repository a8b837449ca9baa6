// The hemisphere rays of one patch, made in passes over all its samples at once so that the
// compiler can vectorise them (float, structure of arrays): Sobol' walk, Owen scramble, then the
// warps (uniform point on the triangle, cosine-weighted direction by the concentric map).
// Making rays must cost little next to tracing them (bench/formfactor_bench.cpp measures it).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "formfactor/formfactor.h"
#include "formfactor/hemisphere_rays.h"
#include "formfactor/sobol.h"
#include "trace/counter_rng.h"
#include "trace/sample_warps.h"

namespace radiosity::formfactor {

std::array<uint32_t, 4> scrambleSeeds(uint64_t seed, int64_t patch, uint32_t stream) {
  auto bits = trace::philox4x32({0, stream, static_cast<uint32_t>(patch),
                                 static_cast<uint32_t>(static_cast<uint64_t>(patch) >> 32)},
                                trace::philoxKey(seed));
  return {bits[0], bits[1], bits[2], bits[3]};
}

namespace {

// Bit reversal with shifts and masks only (no byte swap), so that loops over it vectorise.
inline uint32_t reverseBitsVectorisable(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

// A patch's frame in float, for the warps.
struct FloatFrame {
  float v0x, v0y, v0z, e1x, e1y, e1z, e2x, e2y, e2z, liftX, liftY, liftZ;
  float tx, ty, tz, bx, by, bz, nx, ny, nz;
};

FloatFrame frameOf(const Mesh& patches, int64_t patch, double offset) {
  const trace::PatchFrame frame(patches, patch);
  const Vec3 e1 = frame.v1 - frame.v0, e2 = frame.v2 - frame.v0, lift = offset * frame.normal;
  auto f = [](double v) { return static_cast<float>(v); };
  return {f(frame.v0.x),
          f(frame.v0.y),
          f(frame.v0.z),
          f(e1.x),
          f(e1.y),
          f(e1.z),
          f(e2.x),
          f(e2.y),
          f(e2.z),
          f(lift.x),
          f(lift.y),
          f(lift.z),
          f(frame.tangent.x),
          f(frame.tangent.y),
          f(frame.tangent.z),
          f(frame.bitangent.x),
          f(frame.bitangent.y),
          f(frame.bitangent.z),
          f(frame.normal.x),
          f(frame.normal.y),
          f(frame.normal.z)};
}

// The warps of n samples. Restrict-qualified parameters: the loop vectorises only when the
// compiler knows that nothing aliases (GCC ignores restrict on local pointers).
[[gnu::always_inline]] inline void warp(size_t n, const uint32_t* __restrict b0,
                                        const uint32_t* __restrict b1,
                                        const uint32_t* __restrict b2,
                                        const uint32_t* __restrict b3, const FloatFrame fr,
                                        float* __restrict ox, float* __restrict oy,
                                        float* __restrict oz, float* __restrict dxs,
                                        float* __restrict dys, float* __restrict dzs) {
  const float v0x = fr.v0x, v0y = fr.v0y, v0z = fr.v0z, e1x = fr.e1x, e1y = fr.e1y, e1z = fr.e1z;
  const float e2x = fr.e2x, e2y = fr.e2y, e2z = fr.e2z, liftX = fr.liftX, liftY = fr.liftY,
              liftZ = fr.liftZ;
  const float tx = fr.tx, ty = fr.ty, tz = fr.tz, bx = fr.bx, by = fr.by, bz = fr.bz;
  const float nx = fr.nx, ny = fr.ny, nz = fr.nz;
  constexpr float kQuarter = std::numbers::pi_v<float> / 4;
  constexpr float kUnit = 0x1p-24f;  // top 24 bits: exact in float, in [0, 1)
  for (size_t k = 0; k < n; ++k) {
    // (Through int32: converting unsigned to float does not vectorise.)
    const float u0 = static_cast<float>(static_cast<int32_t>(b0[k] >> 8)) * kUnit;
    const float u1 = static_cast<float>(static_cast<int32_t>(b1[k] >> 8)) * kUnit;
    const float u2 = static_cast<float>(static_cast<int32_t>(b2[k] >> 8)) * kUnit;
    const float u3 = static_cast<float>(static_cast<int32_t>(b3[k] >> 8)) * kUnit;
    // Uniform point on the triangle: p = v0 + √u0 (1 − u1) e1 + √u0 u1 e2.
    const float root = std::sqrt(u0);
    const float w1 = root * (1 - u1), w2 = root * u1;
    ox[k] = v0x + w1 * e1x + w2 * e2x + liftX;
    oy[k] = v0y + w1 * e1y + w2 * e2y + liftY;
    oz[k] = v0z + w1 * e1z + w2 * e2z + liftZ;
    // Concentric map: in the wedge where |a| > |b|, φ = π/4 · b/a and r = a; otherwise
    // φ = π/2 − π/4 · a/b and r = b, i.e. cos and sin trade places.
    const float a = 2 * u2 - 1, b = 2 * u3 - 1;
    const bool major = a * a > b * b;
    const float r = major ? a : b, other = major ? b : a;
    // r = 0 only where other = 0 too; dividing by 1 there keeps the loop free of branches.
    const float t = kQuarter * (other / (r != 0 ? r : 1.0f));
    const float t2 = t * t;
    const float c = 1 + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320))));
    const float s = t * (1 + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040))));
    const float dx = r * (major ? c : s), dy = r * (major ? s : c);
    const float lifted = 1 - dx * dx - dy * dy;
    const float dz = std::sqrt(lifted > 0 ? lifted : 0.0f);
    dxs[k] = dx * tx + dy * bx + dz * nx;
    dys[k] = dx * ty + dy * by + dz * ny;
    dzs[k] = dx * tz + dy * bz + dz * nz;
  }
}

}  // namespace

// Compiled for AVX2 and for the baseline, picked at run time: the scramble's 32-bit multiplies
// and the 8-wide float warps vectorise only with AVX2, and the program must run everywhere.
__attribute__((target_clones("avx2", "default"))) void makeHemisphereRays(
    const Mesh& patches, const HemisphereSamples& samples, SceneTracer::RayBatch& rays,
    std::vector<uint32_t>& scratch) {
  const int64_t patch = samples.patch;
  const auto n = static_cast<size_t>(samples.count);
  rays.resize(n);
  scratch.resize(4 * n);
  uint32_t* bits[4] = {scratch.data(), scratch.data() + n, scratch.data() + 2 * n,
                       scratch.data() + 3 * n};

  // 1. The points of the samples, bit-reversed, one XOR per dimension and step.
  const auto first = static_cast<uint32_t>(samples.firstSample);
  uint32_t reversed[4];
  for (int d = 0; d < 4; ++d) {
    reversed[d] = sobol_detail::reverseBits(sobolBits(sobolPointOfSample(first), d));
  }
  for (size_t k = 0; k < n; ++k) {
    for (int d = 0; d < 4; ++d) bits[d][k] = reversed[d];
    const int flipped = std::countr_zero(static_cast<uint32_t>(first + k + 1));
    for (int d = 0; d < 4; ++d) reversed[d] ^= sobol_detail::kReversedDirections.v[d][flipped];
  }
  // 2. Owen scramble (Laine–Karras on the reversed bits, reversed back).
  const auto seeds = scrambleSeeds(samples.seed, patch, samples.stream);
  for (int d = 0; d < 4; ++d) {
    uint32_t* x = bits[d];
    const uint32_t s = seeds[d];
    for (size_t k = 0; k < n; ++k) {
      x[k] = reverseBitsVectorisable(sobol_detail::laineKarrasPermutation(x[k], s));
    }
  }
  // 3. Warps, in float: the rays go to Embree in float anyway.
  warp(n, bits[0], bits[1], bits[2], bits[3], frameOf(patches, patch, samples.offset),
       rays.originX.data(), rays.originY.data(), rays.originZ.data(), rays.directionX.data(),
       rays.directionY.data(), rays.directionZ.data());
  std::fill(rays.tFar.begin(), rays.tFar.end(), std::numeric_limits<float>::infinity());
}

void hemisphereRays(const Mesh& patches, int64_t patch, int64_t firstSample, int64_t count,
                    uint64_t seed, double offset, SceneTracer::RayBatch& rays) {
  std::vector<uint32_t> scratch;
  makeHemisphereRays(patches, {patch, firstSample, count, seed, offset}, rays, scratch);
}

}  // namespace radiosity::formfactor
