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

/// A point of a plane's coordinates.
using PlanePoint = std::array<double, 2>;

/// The region inside the outline rings[0] and outside the outlines rings[1], rings[2], … (holes
/// cut out of it, which may share corners and edges with the outline and each other),
/// triangulated as meshPlanarPolygon does. Index i is the i-th corner of the rings taken in
/// order (a corner at the point of an earlier one takes that one's index), n + k is added[k].
/// Triangles counter-clockwise. nullopt where edges cross (a hole across the outline or across
/// another hole) or a ring passes one point twice.
std::optional<PolygonTriangles> meshPlanarRegion(const std::vector<std::vector<PlanePoint>>& rings,
                                                 size_t maxAdded);

}  // namespace radiosity::detail
