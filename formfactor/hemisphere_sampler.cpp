// Form-factor rows by cosine-weighted hemisphere sampling: the share of rays from patch i whose
// first hit is the front of patch j estimates F_ij without bias (the cosines and 1/(π r²) of
// the kernel cancel against the sampling density), rows have at most N entries, and in a closed
// scene each row sums to exactly 1.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "formfactor/counter_rng.h"
#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

namespace {

// Random-number streams of one (seed, patch): one for the samples, one for the permutation
// that pairs point strata with direction strata.
constexpr uint32_t kSampleStream = 0;
constexpr uint32_t kPermutationStream = 1;

// Shirley–Chiu concentric map of the unit square onto the unit disk: keeps strata compact.
std::array<double, 2> concentricDisk(double u1, double u2) {
  double a = 2 * u1 - 1, b = 2 * u2 - 1;
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (std::numbers::pi / 4) * (b / a);
  } else {
    r = b;
    phi = (std::numbers::pi / 2) - (std::numbers::pi / 4) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// An orthonormal basis around n (Duff et al., "Building an orthonormal basis, revisited").
void basisAround(Vec3 n, Vec3& t, Vec3& b) {
  double sign = std::copysign(1.0, n.z);
  double a = -1.0 / (sign + n.z);
  double c = n.x * n.y * a;
  t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// A permutation of [0, n) keyed by (seed, patch): Fisher–Yates with counter-based numbers.
std::vector<uint32_t> strataPermutation(uint64_t seed, int64_t patch, uint32_t n) {
  std::vector<uint32_t> p(n);
  std::iota(p.begin(), p.end(), 0u);
  for (uint32_t i = n; i > 1; --i) {
    double u = uniforms(seed, patch, i, kPermutationStream)[0];
    std::swap(p[i - 1], p[static_cast<uint32_t>(u * i)]);
  }
  return p;
}

}  // namespace

SparseRows computeRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress) {
  const auto n = static_cast<uint32_t>(options.raysPerPatch);
  // Points and directions each stratified on an m×m grid of the unit square.
  const auto m = static_cast<uint32_t>(std::max(1.0, std::floor(std::sqrt(double(n)))));
  const uint32_t cells = m * m;
  // Leave the surface by an amount relative to the scene, not an absolute epsilon: Embree
  // works in float, whose rounding grows with the coordinates.
  const double offset = 1e-5 * tracer.sceneSize();

  const bool labelled = patches.hasLabels();
  if (labelled && statistics.backFaceHitsByLabel.size() < patches.labelNames.size()) {
    statistics.backFaceHitsByLabel.resize(patches.labelNames.size(), 0);
  }

  SparseRows rows;
  rows.firstRow = firstPatch;
  statistics.minRowSum = endPatch > firstPatch ? 2.0 : 0.0;
  statistics.maxRowSum = 0.0;
  std::vector<int64_t> hits;
  hits.reserve(n);
  for (int64_t i = firstPatch; i < endPatch; ++i) {
    const Vec3 v0 = patches.corner(i, 0), v1 = patches.corner(i, 1), v2 = patches.corner(i, 2);
    const Vec3 normal = patches.normal(i);
    Vec3 tangent, bitangent;
    basisAround(normal, tangent, bitangent);
    const std::vector<uint32_t> pairing = strataPermutation(options.seed, i, n);

    hits.clear();
    for (uint32_t k = 0; k < n; ++k) {
      const auto u = uniforms(options.seed, i, k, kSampleStream);
      const uint32_t pointCell = k % cells, directionCell = pairing[k] % cells;
      const double pu = (pointCell % m + u[0]) / m, pv = (pointCell / m + u[1]) / m;
      const double du = (directionCell % m + u[2]) / m, dv = (directionCell / m + u[3]) / m;

      // Uniform point on the triangle (area-preserving square-to-triangle map).
      const double root = std::sqrt(pu);
      const Vec3 point = (1 - root) * v0 + (root * (1 - pv)) * v1 + (root * pv) * v2;
      // Cosine-weighted direction (Malley): a uniform disk point lifted to the hemisphere.
      const auto [dx, dy] = concentricDisk(du, dv);
      const double dz = std::sqrt(std::max(0.0, 1 - dx * dx - dy * dy));
      const Vec3 direction = dx * tangent + dy * bitangent + dz * normal;

      ++statistics.raysCast;
      auto hit = tracer.intersect(point + offset * normal, direction, 0.0);
      if (!hit) {
        ++statistics.escapedRays;
      } else if (hit->patch == i || dot(direction, patches.normal(hit->patch)) >= 0) {
        ++statistics.backFaceHits;  // absorbed: the back of a one-sided patch
        if (labelled) ++statistics.backFaceHitsByLabel[patches.label[hit->patch]];
      } else {
        hits.push_back(hit->patch);
      }
    }

    std::sort(hits.begin(), hits.end());
    for (size_t a = 0; a < hits.size();) {
      size_t b = a;
      while (b < hits.size() && hits[b] == hits[a]) ++b;
      rows.column.push_back(hits[a]);
      rows.value.push_back(static_cast<double>(b - a) / n);
      a = b;
    }
    rows.rowStart.push_back(rows.nonzeros());
    const double rowSum = static_cast<double>(hits.size()) / n;
    statistics.minRowSum = std::min(statistics.minRowSum, rowSum);
    statistics.maxRowSum = std::max(statistics.maxRowSum, rowSum);
    statistics.sumRowSums += rowSum;
    if (progress) progress(i - firstPatch + 1);
  }
  return rows;
}

}  // namespace radiosity::formfactor
