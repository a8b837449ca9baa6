// Maps from the unit square to the sampling domains of the form-factor estimators.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

#include "core/mesh.h"

namespace radiosity::trace {

/// cos x and sin x for |x| ≤ π/4 by Taylor polynomials (errors below 3e-7: the direction
/// goes to Embree in float), several times cheaper than a library sincos.
inline std::array<double, 2> cosSinQuarter(double x) {
  const double x2 = x * x;
  const double c = 1 + x2 * (-1.0 / 2 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320))));
  const double s = x * (1 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040))));
  return {c, s};
}

/// Shirley–Chiu concentric map of the unit square onto the unit disk: keeps strata compact.
inline std::array<double, 2> concentricDisk(double u1, double u2) {
  const double a = 2 * u1 - 1, b = 2 * u2 - 1;
  if (a == 0 && b == 0) return {0, 0};
  constexpr double kQuarter = std::numbers::pi / 4;
  if (std::abs(a) > std::abs(b)) {  // φ = π/4 · b/a
    const auto [c, s] = cosSinQuarter(kQuarter * (b / a));
    return {a * c, a * s};
  }
  // φ = π/2 − π/4 · a/b: cos φ = sin(π/4 · a/b), sin φ = cos(π/4 · a/b)
  const auto [c, s] = cosSinQuarter(kQuarter * (a / b));
  return {b * s, b * c};
}

/// An orthonormal basis around n (Duff et al., "Building an orthonormal basis, revisited").
inline void basisAround(Vec3 n, Vec3& t, Vec3& b) {
  // The branch on the sign of n.z must not flip on round-off: a wall's n.z is ±1e-17 or −0
  // depending on the scene's scale, and a flipped sign mirrors every direction of the row.
  const double sign = n.z < -1e-9 ? -1.0 : 1.0;
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

/// Uniform point on triangle (v0, v1, v2): the area-preserving square-to-triangle map.
inline Vec3 pointOnTriangle(Vec3 v0, Vec3 v1, Vec3 v2, double u1, double u2) {
  const double root = std::sqrt(u1);
  return (1 - root) * v0 + (root * (1 - u2)) * v1 + (root * u2) * v2;
}

/// A patch's frame, computed once per row.
struct PatchFrame {
  Vec3 v0, v1, v2, normal, tangent, bitangent;

  PatchFrame(const Mesh& patches, int64_t patch)
      : v0(patches.corner(patch, 0)),
        v1(patches.corner(patch, 1)),
        v2(patches.corner(patch, 2)),
        normal(patches.normal(patch)) {
    basisAround(normal, tangent, bitangent);
  }

  /// Cosine-weighted direction (Malley: a uniform disk point lifted to the hemisphere).
  Vec3 cosineDirection(double u1, double u2) const {
    const auto [dx, dy] = concentricDisk(u1, u2);
    const double dz = std::sqrt(std::max(0.0, 1 - dx * dx - dy * dy));
    return dx * tangent + dy * bitangent + dz * normal;
  }
};

}  // namespace radiosity::trace
