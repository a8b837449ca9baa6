#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

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
std::vector<double> sourceFaceExtents(const Mesh& mesh) {
  int64_t faces = 0;
  for (int64_t f : mesh.sourceFace) faces = std::max(faces, f + 1);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Vec3> lo(faces, Vec3{inf, inf, inf}), hi(faces, Vec3{-inf, -inf, -inf});
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const int64_t f = mesh.sourceFace[t];
    if (f < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.corner(t, k);
      lo[f] = {std::min(lo[f].x, p.x), std::min(lo[f].y, p.y), std::min(lo[f].z, p.z)};
      hi[f] = {std::max(hi[f].x, p.x), std::max(hi[f].y, p.y), std::max(hi[f].z, p.z)};
    }
  }
  std::vector<double> extent(faces, 0);
  for (int64_t f = 0; f < faces; ++f)
    if (lo[f].x <= hi[f].x) {
      const Vec3 span = hi[f] - lo[f];
      extent[f] = std::hypot(span.x, span.y, span.z);
    }
  return extent;
}

}  // namespace

int64_t untraceableTriangle(const Mesh& mesh, double& size, double& distance) {
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  const Vec3 centre = 0.5 * lo + 0.5 * hi;  // (lo + hi overflows at ±1e308)
  const bool byFace = mesh.sourceFace.size() == mesh.triangles.size();
  std::vector<double> faceExtent;  // found when first needed: most meshes never need it
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
    if (byFace && mesh.sourceFace[t] >= 0) {
      if (faceExtent.empty()) faceExtent = sourceFaceExtents(mesh);
      if (!(faceExtent[mesh.sourceFace[t]] < kTraceableShare * distance)) continue;
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
