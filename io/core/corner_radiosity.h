// Smooth shading: radiosity at each patch corner, averaged over the patches around the vertex
// that lie in the same surface (a crease stays sharp), and the interpolation inside a patch. The
// renderer shades with it, the discretisation error compares against it, and the result file's
// display mesh (/display, for ParaView) carries it as point data.
#pragma once

#include <array>
#include <vector>

#include "io/core/mesh.h"

namespace radiosity {

/// Radiosity at the three corners of every patch, indexed [patch][corner].
using CornerRadiosity = std::vector<std::array<Rgb, 3>>;

/// Patches whose normals differ by more than this are not averaged: a crease stays sharp.
inline constexpr double kCreaseDegrees = 30;

/// Each corner's value is the area-weighted mean of B over the patches that share the vertex
/// (by position, so duplicated vertices count as one) and whose normal is within
/// `creaseDegrees` of this patch's normal; the patch itself always counts. `normal`, `area`
/// and `radiosity` hold one entry per triangle of `mesh`.
CornerRadiosity cornerRadiosity(const Mesh& mesh, const std::vector<Vec3>& normal,
                                const std::vector<double>& area, const std::vector<Rgb>& radiosity,
                                double creaseDegrees = kCreaseDegrees);

/// A mesh to show B smooth with a viewer's point data: one vertex per distinct pair of position
/// and corner value, so that corners in one surface share a vertex and a crease splits it (a
/// viewer interpolating point data then shades as the renderer does).
struct DisplayMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;  ///< one per patch, in the patches' order
  std::vector<Rgb> radiosity;       ///< per vertex
};
DisplayMesh displayMesh(const Mesh& mesh, const CornerRadiosity& corners);

/// The value at barycentric (u, v): (1-u-v)·c0 + u·c1 + v·c2, as SceneTracer::Hit reports them.
inline Rgb interpolate(const std::array<Rgb, 3>& corner, double u, double v) {
  double w = 1 - u - v;
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = w * corner[0][c] + u * corner[1][c] + v * corner[2][c];
  return out;
}

}  // namespace radiosity
