// Maps from the unit square to the sampling domains of the form-factor estimators.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

#include "io/io.h"

namespace radiosity::formfactor {

/// Shirley–Chiu concentric map of the unit square onto the unit disk: keeps strata compact.
inline std::array<double, 2> concentricDisk(double u1, double u2) {
  const double a = 2 * u1 - 1, b = 2 * u2 - 1;
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

/// An orthonormal basis around n (Duff et al., "Building an orthonormal basis, revisited").
inline void basisAround(Vec3 n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n.z);
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

}  // namespace radiosity::formfactor
