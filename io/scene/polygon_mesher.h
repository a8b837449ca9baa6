// Private to io/scene/: triangulatePolygon's way for polygons whose ear clipping is ill-shaped.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace radiosity::detail {

/// Triangles over the corners of a polygon and the points added inside it, in its plane's
/// coordinates: index i < n is corner i, n + k is added[k].
struct PolygonTriangles {
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<double, 2>> added;
};

/// The simple polygon (u[i], v[i]), counter-clockwise, triangulated with points added inside
/// (at most `maxAdded`; never on its outline) so that no angle is below ~20.7° where the
/// outline allows: CGAL's constrained Delaunay refinement. Triangles counter-clockwise.
/// nullopt for an outline it cannot take as one simple polygon (corners at one point, edges
/// that touch).
std::optional<PolygonTriangles> meshPlanarPolygon(const std::vector<double>& u,
                                                  const std::vector<double>& v, size_t maxAdded);

}  // namespace radiosity::detail
