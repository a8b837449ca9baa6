// Coarsening by undoing bisections: a vertex that is exactly the midpoint of an edge a–b, whose
// triangles are the two halves of one triangle across a–b (or of the two that shared it), is
// removed and each pair of halves merged back. What refinement made where B turned out flat is
// taken back, and the mesh stays conforming: the edges around the star are kept as they are.
#include <algorithm>
#include <numeric>
#include <optional>
#include <string>

#include "core/error.h"
#include "partition/partition.h"

namespace radiosity::partition {

namespace {

// Per vertex, the triangles that use it (CSR).
struct VertexStars {
  std::vector<int64_t> first;
  std::vector<int64_t> triangles;
};

VertexStars starsOf(const Mesh& mesh) {
  VertexStars stars;
  stars.first.assign(mesh.vertices.size() + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int64_t v : t) ++stars.first[v + 1];
  std::partial_sum(stars.first.begin(), stars.first.end(), stars.first.begin());
  std::vector<int64_t> next(stars.first.begin(), stars.first.end() - 1);
  stars.triangles.resize(stars.first.back());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    for (int64_t v : mesh.triangles[t]) stars.triangles[next[v]++] = t;
  return stars;
}

bool sameSurface(const Mesh& mesh, int64_t s, int64_t t) {
  return mesh.sourceFace[s] == mesh.sourceFace[t] && mesh.reflectance[s] == mesh.reflectance[t] &&
         mesh.emission[s] == mesh.emission[t] &&
         (!mesh.hasLabels() || mesh.label[s] == mesh.label[t]);
}

// Corner k of triangle t is `vertex`; the corner after it and the one before.
int cornerOf(const Triangle& t, int64_t vertex) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == vertex) return k;
  return -1;
}

// The bisection `vertex` would undo, if its star has the halves' shape: 2 or 4 triangles, each
// with one corner on a line a–b through the vertex (the vertex exactly their midpoint, as
// refinement computed it) and one apex, two triangles per apex, one on each side, alike in face
// and material. Of two such lines (the centre of a square cut along both diagonals), the one
// with the smaller end.
std::optional<Bisection> bisectionAt(const Mesh& mesh, const VertexStars& stars, int64_t vertex) {
  const int64_t begin = stars.first[vertex], count = stars.first[vertex + 1] - begin;
  if (count != 2 && count != 4) return std::nullopt;
  std::vector<int64_t> around;  // the corners of the star other than the vertex
  for (int64_t s = begin; s < begin + count; ++s)
    for (int64_t v : mesh.triangles[stars.triangles[s]])
      if (v != vertex) around.push_back(v);
  std::sort(around.begin(), around.end());
  around.erase(std::unique(around.begin(), around.end()), around.end());
  const Vec3 m = mesh.vertices[vertex];
  for (size_t i = 0; i < around.size(); ++i) {
    for (size_t j = i + 1; j < around.size(); ++j) {
      const int64_t a = around[i], b = around[j];
      if (0.5 * (mesh.vertices[a] + mesh.vertices[b]) != m) continue;
      // Per triangle, its apex (the corner not a, b or the vertex) and which end it holds.
      Bisection found{vertex, {a, b}, {-1, -1, -1, -1}};
      bool shaped = true;
      int pairs = 0;
      std::array<int64_t, 2> apex{-1, -1};
      for (int64_t s = begin; s < begin + count && shaped; ++s) {
        const int64_t t = stars.triangles[s];
        const Triangle& tri = mesh.triangles[t];
        const bool hasA = cornerOf(tri, a) >= 0, hasB = cornerOf(tri, b) >= 0;
        if (hasA == hasB) {
          shaped = false;
          break;
        }
        int64_t c = -1;
        for (int64_t v : tri)
          if (v != vertex && v != a && v != b) c = v;
        int p = apex[0] == c ? 0 : apex[1] == c ? 1 : -1;
        if (p < 0) {
          if (pairs == 2) {
            shaped = false;
            break;
          }
          p = pairs++;
          apex[p] = c;
        }
        int64_t& slot = found.halves[2 * p + (hasA ? 0 : 1)];
        if (slot >= 0) shaped = false;
        slot = t;
      }
      if (!shaped || 2 * pairs != count) continue;
      for (int p = 0; p < pairs; ++p)
        if (found.halves[2 * p] < 0 || found.halves[2 * p + 1] < 0 ||
            !sameSurface(mesh, found.halves[2 * p], found.halves[2 * p + 1]))
          shaped = false;
      if (shaped) return found;
    }
  }
  return std::nullopt;
}

}  // namespace

std::vector<Bisection> undoableBisections(const Mesh& mesh) {
  const VertexStars stars = starsOf(mesh);
  std::vector<Bisection> found;
  for (int64_t v = 0; v < static_cast<int64_t>(mesh.vertices.size()); ++v)
    if (std::optional<Bisection> b = bisectionAt(mesh, stars, v)) found.push_back(*b);
  return found;
}

Mesh undoBisections(const Mesh& mesh, const std::vector<int64_t>& vertices,
                    std::vector<std::array<int64_t, 2>>* halvesOf) {
  const VertexStars stars = starsOf(mesh);
  const int64_t n = mesh.triangleCount(), nv = static_cast<int64_t>(mesh.vertices.size());
  // Per triangle: -1 kept as it is, -2 dropped (merged into the pair's first half), else the
  // pair's second half (it heads the pair, and takes the parent's corners).
  std::vector<int64_t> pairedWith(n, -1);
  std::vector<Triangle> parentCorners(n);
  std::vector<char> removed(nv, 0);
  for (int64_t v : vertices) {
    std::optional<Bisection> b;
    if (v >= 0 && v < nv && !removed[v]) b = bisectionAt(mesh, stars, v);
    if (!b)
      throw Error(exit_code::kFailure, "coarsening: vertex " + std::to_string(v) +
                                           " is not the midpoint of a bisection to undo");
    for (int64_t t : b->halves)
      if (t >= 0 && pairedWith[t] != -1)
        throw Error(exit_code::kFailure, "coarsening: the bisections at vertex " +
                                             std::to_string(v) + " and another share a triangle");
    removed[v] = 1;
    for (int p = 0; p < 2 && b->halves[2 * p] >= 0; ++p) {
      const int64_t withA = b->halves[2 * p], withB = b->halves[2 * p + 1];
      const int64_t head = std::min(withA, withB), tail = std::max(withA, withB);
      pairedWith[head] = tail;
      pairedWith[tail] = -2;
      // The half with end a becomes the parent by taking b in the vertex's place, which keeps
      // its winding (the halves (a, m, c) and (m, b, c) of (a, b, c)).
      Triangle parent = mesh.triangles[withA];
      parent[cornerOf(parent, v)] = b->ends[1];
      parentCorners[head] = parent;
    }
  }
  // The vertices kept, renumbered in order.
  std::vector<int64_t> renumbered(nv, -1);
  Mesh out;
  for (int64_t v = 0, next = 0; v < nv; ++v) {
    if (removed[v]) continue;
    renumbered[v] = next++;
    out.vertices.push_back(mesh.vertices[v]);
  }
  if (halvesOf) halvesOf->clear();
  for (int64_t t = 0; t < n; ++t) {
    if (pairedWith[t] == -2) continue;
    Triangle corners = pairedWith[t] >= 0 ? parentCorners[t] : mesh.triangles[t];
    for (int64_t& v : corners) v = renumbered[v];
    out.triangles.push_back(corners);
    out.sourceFace.push_back(mesh.sourceFace[t]);
    out.reflectance.push_back(mesh.reflectance[t]);
    out.emission.push_back(mesh.emission[t]);
    if (mesh.hasLabels()) out.label.push_back(mesh.label[t]);
    if (halvesOf) halvesOf->push_back({t, pairedWith[t]});
  }
  out.labelNames = mesh.labelNames;
  out.labelEmissivity = mesh.labelEmissivity;
  out.warnings = mesh.warnings;
  out.lengthUnit = mesh.lengthUnit;
  out.sourceFiles = mesh.sourceFiles;
  return out;
}

}  // namespace radiosity::partition
