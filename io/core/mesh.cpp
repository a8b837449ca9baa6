#include <algorithm>
#include <cmath>
#include <limits>

#include "io/core/mesh.h"

namespace radiosity {

double Mesh::area(int64_t t) const {
  return 0.5 * length(cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0)));
}

Vec3 Mesh::normal(int64_t t) const {
  return normalize(cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0)));
}

Vec3 Mesh::centroid(int64_t t) const {
  return (1.0 / 3.0) * (corner(t, 0) + corner(t, 1) + corner(t, 2));
}

void Mesh::boundingBox(Vec3& lo, Vec3& hi) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  lo = {inf, inf, inf};
  hi = {-inf, -inf, -inf};
  for (const Vec3& v : vertices) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], v[k]);
      hi[k] = std::max(hi[k], v[k]);
    }
  }
}

TracingFrame normaliseForTracing(Mesh& mesh) {
  TracingFrame frame;
  if (mesh.vertices.empty()) return frame;
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  frame.centre = 0.5 * (lo + hi);
  const double diagonal = length(hi - lo);
  frame.scale = std::isfinite(diagonal) && diagonal > 0 ? diagonal : 1.0;
  for (Vec3& v : mesh.vertices) v = frame.toFrame(v);
  return frame;
}

double Mesh::totalArea() const {
  double sum = 0;
  for (int64_t t = 0; t < triangleCount(); ++t) sum += area(t);
  return sum;
}

}  // namespace radiosity
