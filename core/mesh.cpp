#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/mesh.h"

namespace radiosity {
namespace {

// The cross product of triangle t's edges, the edges first scaled by the power of two 2^-k that
// brings the larger to [1, 2): scaling by a power of two is exact, and at 1e-150 (or 1e30) the
// plain product of two lengths underflows (or its square overflows). Returns it and sets k.
Vec3 scaledCross(const Mesh& mesh, int64_t t, int& k) {
  const Vec3 e1 = mesh.corner(t, 1) - mesh.corner(t, 0), e2 = mesh.corner(t, 2) - mesh.corner(t, 0);
  double largest = 0;
  for (int i = 0; i < 3; ++i) largest = std::max({largest, std::abs(e1[i]), std::abs(e2[i])});
  k = largest > 0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
  const auto scaled = [k](Vec3 e) {
    return Vec3{std::ldexp(e.x, -k), std::ldexp(e.y, -k), std::ldexp(e.z, -k)};
  };
  return cross(scaled(e1), scaled(e2));
}

}  // namespace

double Mesh::area(int64_t t) const {
  int k = 0;
  const Vec3 n = scaledCross(*this, t, k);
  return std::ldexp(0.5 * length(n), 2 * k);
}

Vec3 Mesh::normal(int64_t t) const {
  int k = 0;
  return normalize(scaledCross(*this, t, k));
}

Vec3 Mesh::centroid(int64_t t) const {
  return (1.0 / 3.0) * (corner(t, 0) + corner(t, 1) + corner(t, 2));
}

void Mesh::boundingBox(Vec3& lo, Vec3& hi) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  lo = {inf, inf, inf};
  hi = {-inf, -inf, -inf};
  for (const Triangle& t : triangles) {
    for (int64_t i : t) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], vertices[i][k]);
        hi[k] = std::max(hi[k], vertices[i][k]);
      }
    }
  }
}

TracingFrame normaliseForTracing(Mesh& mesh) {
  TracingFrame frame;
  if (mesh.triangles.empty()) return frame;
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  frame.centre = 0.5 * (lo + hi);
  const Vec3 span = hi - lo;
  const double diagonal = std::hypot(span.x, span.y, span.z);  // (no underflow at 1e-155)
  frame.scale = std::isfinite(diagonal) && diagonal > 0 ? diagonal : 1.0;
  for (Vec3& v : mesh.vertices) v = frame.toFrame(v);
  return frame;
}

namespace {

// Each source face's extent: the diagonal of the bounding box of the triangles cut from it.
// Keyed by face id, which a result file may give any value.
std::unordered_map<int64_t, double> sourceFaceExtents(const Mesh& mesh) {
  std::unordered_map<int64_t, std::pair<Vec3, Vec3>> box;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.corner(t, k);
      auto [at, added] = box.try_emplace(mesh.sourceFace[t], p, p);
      Vec3 &lo = at->second.first, &hi = at->second.second;
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  std::unordered_map<int64_t, double> extent;
  for (const auto& [face, b] : box) {
    const Vec3 span = b.second - b.first;
    extent[face] = std::hypot(span.x, span.y, span.z);
  }
  return extent;
}

}  // namespace

int64_t untraceableTriangle(const Mesh& mesh, double& size, double& distance) {
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  const Vec3 centre = 0.5 * lo + 0.5 * hi;  // (lo + hi overflows at ±1e308)
  const bool byFace = mesh.sourceFace.size() == mesh.triangles.size();
  std::unordered_map<int64_t, double>
      faceExtent;  // found when first needed: most meshes never need it
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    size = distance = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 edge = mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k);
      const Vec3 out = mesh.corner(t, k) - centre;
      size = std::max(size, std::hypot(edge.x, edge.y, edge.z));
      distance = std::max(distance, std::hypot(out.x, out.y, out.z));
    }
    if (!(size < kTraceableShare * distance)) continue;
    // A piece the mesh cut from a traceable face (a contact's sliver) is traced as that face
    // is: a hit misplaced by the float rounding moves between pieces of one surface.
    if (byFace) {
      if (faceExtent.empty()) faceExtent = sourceFaceExtents(mesh);
      if (!(faceExtent.at(mesh.sourceFace[t]) < kTraceableShare * distance)) continue;
    }
    return t;
  }
  return -1;
}

std::string tracingProblem(const Mesh& mesh) {
  auto number = [](double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", x);
    return std::string(text);
  };
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        const double x = mesh.corner(t, k)[axis];
        if (!std::isfinite(x) || std::abs(x) > kMaxCoordinate)
          return "vertex " + std::to_string(mesh.triangles[t][k] + 1) +
                 " (counting from 1) has coordinate " + number(x) +
                 " (must be finite, |x| <= 1e30)";
      }
    }
  }
  double size = 0, distance = 0;
  const int64_t t = untraceableTriangle(mesh, size, distance);
  if (t < 0) return "";
  const std::string face =
      static_cast<size_t>(t) < mesh.sourceFace.size()
          ? " (face " + std::to_string(mesh.sourceFace[t] + 1) + ", counting from 1)"
          : "";
  return "triangle " + std::to_string(t) + face + " is " + number(size) + " across at " +
         number(distance) +
         " from the scene's centre: rays are traced in float, which resolves no less than 1e-5 "
         "of that distance; leave out the far-off geometry or trace the parts as scenes of "
         "their own";
}

double Mesh::totalArea() const {
  double sum = 0;
  for (int64_t t = 0; t < triangleCount(); ++t) sum += area(t);
  return sum;
}

}  // namespace radiosity
