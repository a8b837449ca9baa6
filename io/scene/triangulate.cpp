// Ear clipping of the polygons OBJ faces may be. A fan would cover concave polygons wrongly.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "io/scene/scene_internal.h"

namespace radiosity::detail {
namespace {

std::vector<std::array<int, 3>> fan(const std::vector<int>& ring) {
  std::vector<std::array<int, 3>> out;
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.push_back({ring[0], ring[i], ring[i + 1]});
  return out;
}

// Newell's normal: the area vector of the outline, pointing to the side it winds around
// counter-clockwise; robust for slightly non-planar polygons.
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

// The polygon's corners in the plane through its first corner with unit normal `normal`.
void planeCoordinates(const std::vector<Vec3>& polygon, Vec3 normal, std::vector<double>& u,
                      std::vector<double>& v) {
  const Vec3 helper = std::abs(normal.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalize(cross(helper, normal));
  const Vec3 e2 = cross(normal, e1);
  u.resize(polygon.size());
  v.resize(polygon.size());
  for (size_t i = 0; i < polygon.size(); ++i) {
    u[i] = dot(polygon[i] - polygon[0], e1);
    v[i] = dot(polygon[i] - polygon[0], e2);
  }
}

}  // namespace

std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<Vec3>& polygon) {
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
