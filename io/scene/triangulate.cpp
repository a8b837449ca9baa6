// Triangulation of the polygons scene files' faces may be: ear clipping (a fan would cover
// concave polygons wrongly), or a quality mesh where ear clipping leaves needles.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "io/scene/polygon_mesher.h"
#include "io/scene/scene_internal.h"

namespace radiosity::detail {

// Robust for slightly non-planar polygons.
Vec3 newellNormal(const std::vector<Vec3>& polygon) {
  const size_t n = polygon.size();
  Vec3 normal;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = polygon[i], b = polygon[(i + 1) % n];
    normal.x += (a.y - b.y) * (a.z + b.z);
    normal.y += (a.z - b.z) * (a.x + b.x);
    normal.z += (a.x - b.x) * (a.y + b.y);
  }
  return normal;
}

namespace {

std::vector<std::array<int, 3>> fan(const std::vector<int>& ring) {
  std::vector<std::array<int, 3>> out;
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.push_back({ring[0], ring[i], ring[i + 1]});
  return out;
}

// Unit axes of the plane with unit normal `normal`: e1 × e2 = normal, so an outline
// counter-clockwise about the normal is counter-clockwise in (e1, e2).
std::array<Vec3, 2> planeAxes(Vec3 normal) {
  const Vec3 helper = std::abs(normal.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalize(cross(helper, normal));
  return {e1, cross(normal, e1)};
}

// The polygon's corners in the plane through its first corner with unit normal `normal`.
void planeCoordinates(const std::vector<Vec3>& polygon, Vec3 normal, std::vector<double>& u,
                      std::vector<double>& v) {
  const auto [e1, e2] = planeAxes(normal);
  u.resize(polygon.size());
  v.resize(polygon.size());
  for (size_t i = 0; i < polygon.size(); ++i) {
    u[i] = dot(polygon[i] - polygon[0], e1);
    v[i] = dot(polygon[i] - polygon[0], e2);
  }
}

/// √3·(longest edge)² / (4·area), as the meshing report gives it: 1 for equilateral.
double aspectRatio(Vec3 a, Vec3 b, Vec3 c) {
  const double longest = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
  const double area = 0.5 * length(cross(b - a, c - a));
  return area > 0 ? std::sqrt(3.0) * longest / (4 * area) : INFINITY;
}

double worstAspect(const PolygonTriangulation& t, const std::vector<Vec3>& polygon) {
  auto point = [&](int i) {
    return i < static_cast<int>(polygon.size()) ? polygon[i] : t.added[i - polygon.size()];
  };
  double worst = 1;
  for (const auto& [a, b, c] : t.triangles)
    worst = std::max(worst, aspectRatio(point(a), point(b), point(c)));
  return worst;
}

/// Ear clipping with no needles left, and a worse triangle than the refinement gives it, is
/// taken; above it the polygon is refined (a regular 20-gon's fan reaches 10; the disc of 5,000
/// corners, 2,757).
constexpr double kNeedleAspect = 10;

/// Corners farther than this from the best-fit plane (relative to the polygon's size) keep
/// the ear clipping: points added in a plane would lie off such a surface.
constexpr double kPlanarTolerance = 1e-6;

/// The quality mesh of a planar polygon, in 3D, or nullopt if the polygon is not planar or
/// the mesher does not take its outline.
std::optional<PolygonTriangulation> refinedTriangulation(const std::vector<Vec3>& polygon,
                                                         Vec3 normal) {
  Vec3 centre;
  for (const Vec3& p : polygon) centre = centre + p;
  centre = (1.0 / static_cast<double>(polygon.size())) * centre;
  double size = 0, offPlane = 0;
  for (const Vec3& p : polygon) {
    size = std::max(size, length(p - centre));
    offPlane = std::max(offPlane, std::abs(dot(p - centre, normal)));
  }
  if (!(offPlane <= kPlanarTolerance * size)) return std::nullopt;
  const auto [e1, e2] = planeAxes(normal);
  std::vector<double> u(polygon.size()), v(polygon.size());
  for (size_t i = 0; i < polygon.size(); ++i) {
    u[i] = dot(polygon[i] - centre, e1);
    v[i] = dot(polygon[i] - centre, e2);
  }
  // Enough for a graded mesh (a disc of n corners takes about n); a bound on the work.
  const std::optional<PolygonTriangles> mesh = meshPlanarPolygon(u, v, 4 * polygon.size());
  if (!mesh) return std::nullopt;
  PolygonTriangulation out;
  out.triangles = mesh->triangles;
  for (const auto& [a, b] : mesh->added) out.added.push_back(centre + a * e1 + b * e2);
  return out;
}

/// Ear clipping: trying position 1 first makes a convex polygon come out as the fan from
/// vertex 0.
std::vector<std::array<int, 3>> earClipping(const std::vector<Vec3>& polygon) {
  const int n = static_cast<int>(polygon.size());
  std::vector<int> ring(n);
  std::iota(ring.begin(), ring.end(), 0);
  if (n <= 3) return fan(ring);

  Vec3 normal = newellNormal(polygon);
  if (!(length(normal) > 0)) return fan(ring);  // zero area: whatever we do is degenerate
  normal = normalize(normal);

  // Coordinates in the best-fit plane, oriented so the outline is counter-clockwise.
  std::vector<double> u, v;
  planeCoordinates(polygon, normal, u, v);
  auto orient = [&](int a, int b, int c) {
    return (u[b] - u[a]) * (v[c] - v[a]) - (v[b] - v[a]) * (u[c] - u[a]);
  };
  auto samePoint = [&](int a, int b) { return u[a] == u[b] && v[a] == v[b]; };

  std::vector<std::array<int, 3>> out;
  while (ring.size() > 3) {
    const size_t m = ring.size();
    bool clipped = false;
    // Trying position 1 first makes a convex polygon come out as the fan from vertex 0.
    for (size_t k = 0; k < m && !clipped; ++k) {
      const size_t i = (k + 1) % m;
      const int a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (orient(a, b, c) <= 0) continue;  // reflex or straight corner: not an ear
      bool blocked = false;
      for (int q : ring) {
        if (samePoint(q, a) || samePoint(q, b) || samePoint(q, c)) continue;
        if (orient(a, b, q) >= 0 && orient(b, c, q) >= 0 && orient(c, a, q) >= 0) {
          blocked = true;  // another vertex inside or on the ear: cutting it would overlap
          break;
        }
      }
      if (blocked) continue;
      out.push_back({a, b, c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) {  // self-intersecting outline: no clean answer exists, cover the rest
      for (const auto& t : fan(ring)) out.push_back(t);
      return out;
    }
  }
  out.push_back({ring[0], ring[1], ring[2]});
  return out;
}

}  // namespace

PolygonTriangulation triangulatePolygon(const std::vector<Vec3>& polygon) {
  PolygonTriangulation ears{earClipping(polygon), {}};
  if (polygon.size() <= 4) return ears;
  const double earsWorst = worstAspect(ears, polygon);
  if (earsWorst <= kNeedleAspect) return ears;
  const Vec3 normal = newellNormal(polygon);
  if (!(length(normal) > 0)) return ears;
  std::optional<PolygonTriangulation> refined = refinedTriangulation(polygon, normalize(normal));
  if (!refined || !(worstAspect(*refined, polygon) < earsWorst)) return ears;
  return std::move(*refined);
}

std::vector<Triangle> AddedVertices::triangles(const PolygonTriangulation& polygon,
                                               const std::vector<int64_t>& corners) {
  const auto first = static_cast<int64_t>(points_.size());
  points_.insert(points_.end(), polygon.added.begin(), polygon.added.end());
  const auto n = static_cast<int>(corners.size());
  std::vector<Triangle> out;
  out.reserve(polygon.triangles.size());
  for (const auto& t : polygon.triangles) {
    Triangle triangle;
    for (int k = 0; k < 3; ++k) triangle[k] = t[k] < n ? corners[t[k]] : -1 - (first + t[k] - n);
    out.push_back(triangle);
  }
  return out;
}

void AddedVertices::appendTo(Mesh& mesh) const {
  if (points_.empty()) return;
  const auto base = static_cast<int64_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), points_.begin(), points_.end());
  for (Triangle& t : mesh.triangles)
    for (int64_t& i : t)
      if (i < 0) i = base - 1 - i;
}

std::optional<int64_t> repeatedCorner(const std::vector<int64_t>& corners) {
  // Sorted by (vertex, position): a repeat is a run of equal vertices, and the corner that
  // repeats first is the run's second entry with the lowest position.
  std::vector<std::pair<int64_t, size_t>> sorted(corners.size());
  for (size_t k = 0; k < corners.size(); ++k) sorted[k] = {corners[k], k};
  std::sort(sorted.begin(), sorted.end());
  std::optional<size_t> first;
  for (size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k].first == sorted[k - 1].first && (!first || sorted[k].second < *first))
      first = sorted[k].second;
  }
  if (!first) return std::nullopt;
  return corners[*first];
}

std::string repeatedCornerProblem(const std::string& face, int64_t vertex) {
  return face + " names vertex " + std::to_string(vertex) + " twice: the outline of a face of " +
         "more than 3 corners that passes a vertex twice is ambiguous; give each corner its own "
         "vertex or split the face";
}

bool crossesItself(const std::vector<Vec3>& polygon) {
  const int n = static_cast<int>(polygon.size());
  if (n < 4) return false;
  // A plane: Newell's normal, or for an outline whose signed areas cancel (a symmetric bowtie
  // has none) the normal of its first corner that is not straight.
  Vec3 normal = newellNormal(polygon);
  double scale = 0;
  for (int i = 1; i < n; ++i) scale = std::max(scale, length(polygon[i] - polygon[0]));
  if (!(length(normal) > 1e-12 * scale * scale)) {
    for (int i = 0; i < n && !(length(normal) > 0); ++i)
      normal = cross(polygon[(i + 1) % n] - polygon[i], polygon[(i + 2) % n] - polygon[i]);
  }
  if (!(length(normal) > 0)) return false;  // every corner on a line: degenerate, not crossed
  std::vector<double> u, v;
  planeCoordinates(polygon, normalize(normal), u, v);
  auto orient = [&](int a, int b, int c) {
    const double o = (u[b] - u[a]) * (v[c] - v[a]) - (v[b] - v[a]) * (u[c] - u[a]);
    return (o > 0) - (o < 0);
  };
  for (int i = 0; i < n; ++i) {
    const int a = i, b = (i + 1) % n;
    for (int j = i + 2; j < n; ++j) {
      const int c = j, d = (j + 1) % n;
      if (d == a) continue;  // the edge before the first: they share corner a
      // Proper crossing only: each edge's ends strictly on both sides of the other.
      if (orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0)
        return true;
    }
  }
  return false;
}

}  // namespace radiosity::detail

namespace radiosity::detail {
namespace {

/// The plane coordinates that keep a file's numbers: the two axes other than the normal's
/// largest component, in the order that keeps the outline's winding.
struct AxisProjection {
  int drop = 2, u = 0, v = 1;
  explicit AxisProjection(Vec3 normal) {
    const double n[3] = {normal.x, normal.y, normal.z};
    for (int k = 0; k < 3; ++k)
      if (std::abs(n[k]) > std::abs(n[drop])) drop = k;
    u = (drop + 1) % 3;
    v = (drop + 2) % 3;
    if (n[drop] < 0) std::swap(u, v);
  }
  PlanePoint operator()(Vec3 p) const { return {p[u], p[v]}; }
};

double segmentDistance(PlanePoint p, PlanePoint a, PlanePoint b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  const double t =
      len2 > 0 ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

}  // namespace

bool insidePolygon(const std::vector<Vec3>& polygon, Vec3 p, double tolerance) {
  const AxisProjection project(newellNormal(polygon));
  const PlanePoint q = project(p);
  bool inside = false;
  const size_t n = polygon.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const PlanePoint a = project(polygon[i]), b = project(polygon[j]);
    if (segmentDistance(q, a, b) <= tolerance) return true;
    if ((a[1] > q[1]) != (b[1] > q[1]) &&
        q[0] < b[0] + (q[1] - b[1]) * (a[0] - b[0]) / (a[1] - b[1]))
      inside = !inside;
  }
  return inside;
}

std::optional<PolygonTriangulation> triangulateWithHoles(
    const std::vector<Vec3>& outline, const std::vector<std::vector<Vec3>>& holes) {
  const Vec3 normal = newellNormal(outline);
  if (!(length(normal) > 0)) return std::nullopt;
  const AxisProjection project(normal);
  std::vector<std::vector<PlanePoint>> rings{{}};
  std::vector<Vec3> corners = outline;
  for (const Vec3& p : outline) rings[0].push_back(project(p));
  double expectedArea = 0.5 * length(normal);
  for (const auto& hole : holes) {
    rings.emplace_back();
    for (const Vec3& p : hole) rings.back().push_back(project(p));
    corners.insert(corners.end(), hole.begin(), hole.end());
    expectedArea -= 0.5 * length(newellNormal(hole));
  }
  size_t cornerCount = corners.size();
  const std::optional<PolygonTriangles> mesh = meshPlanarRegion(rings, 4 * cornerCount);
  if (!mesh) return std::nullopt;
  // Added points lifted onto the outline's plane: normal · (p − outline[0]) = 0.
  const Vec3 unit = normalize(normal);
  PolygonTriangulation out;
  out.triangles = mesh->triangles;
  for (const auto& [a, b] : mesh->added) {
    Vec3 p = outline[0];
    p[project.u] = a;
    p[project.v] = b;
    const Vec3 off = p - outline[0];
    p[project.drop] -= dot(off, unit) / unit[project.drop];
    out.added.push_back(p);
  }
  auto point = [&](int i) {
    return i < static_cast<int>(cornerCount) ? corners[i] : out.added[i - cornerCount];
  };
  double area = 0;
  for (const auto& [a, b, c] : out.triangles)
    area += 0.5 * length(cross(point(b) - point(a), point(c) - point(a)));
  if (!(std::abs(area - expectedArea) <= 1e-9 * 0.5 * length(normal))) return std::nullopt;
  return out;
}

}  // namespace radiosity::detail
