#include "io/core/corner_radiosity.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace radiosity {

namespace {

// One id per distinct vertex position: meshes written by other tools may repeat a vertex for
// each face, and smoothing must still see the faces as neighbours.
std::vector<int64_t> weldByPosition(const std::vector<Vec3>& vertices) {
  std::vector<int64_t> order(vertices.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int64_t>(i);
  auto key = [&](int64_t i) {
    const Vec3& p = vertices[i];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return key(a) < key(b); });
  std::vector<int64_t> id(vertices.size());
  int64_t next = -1;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || key(order[k]) != key(order[k - 1])) ++next;
    id[order[k]] = next;
  }
  return id;
}

}  // namespace

CornerRadiosity cornerRadiosity(const Mesh& mesh, const std::vector<Vec3>& normal,
                                const std::vector<double>& area, const std::vector<Rgb>& radiosity,
                                double creaseDegrees) {
  const int64_t n = mesh.triangleCount();
  std::vector<int64_t> welded = weldByPosition(mesh.vertices);
  int64_t vertexCount = 0;
  for (int64_t id : welded) vertexCount = std::max(vertexCount, id + 1);

  // Patches around each (welded) vertex, in CSR form.
  std::vector<int64_t> start(vertexCount + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int64_t v : t) ++start[welded[v] + 1];
  for (int64_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  std::vector<int64_t> patches(start.back());
  std::vector<int64_t> fill(start.begin(), start.end() - 1);
  for (int64_t t = 0; t < n; ++t)
    for (int64_t v : mesh.triangles[t]) patches[fill[welded[v]]++] = t;

  // A small tolerance so that exactly coplanar neighbours never drop out by rounding.
  const double minCos = std::cos(creaseDegrees * std::numbers::pi / 180) - 1e-9;
  CornerRadiosity out(n);
  for (int64_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      int64_t v = welded[mesh.triangles[t][k]];
      Rgb sum{0, 0, 0};
      double weight = 0;
      for (int64_t i = start[v]; i < start[v + 1]; ++i) {
        int64_t s = patches[i];
        if (s != t && !(dot(normal[s], normal[t]) >= minCos)) continue;
        for (int c = 0; c < 3; ++c) sum[c] += area[s] * radiosity[s][c];
        weight += area[s];
      }
      // Only zero-area patches around the vertex: fall back to the patch's own value.
      for (int c = 0; c < 3; ++c) out[t][k][c] = weight > 0 ? sum[c] / weight : radiosity[t][c];
      // B near the largest double overflows the sum: the mean again, from shares of the weight.
      if (weight > 0 && !std::isfinite(sum[0] + sum[1] + sum[2])) {
        out[t][k] = Rgb{0, 0, 0};
        for (int64_t i = start[v]; i < start[v + 1]; ++i) {
          int64_t s = patches[i];
          if (s != t && !(dot(normal[s], normal[t]) >= minCos)) continue;
          for (int c = 0; c < 3; ++c) out[t][k][c] += area[s] / weight * radiosity[s][c];
        }
      }
    }
  }
  return out;
}

DisplayMesh displayMesh(const Mesh& mesh, const CornerRadiosity& corners) {
  const std::vector<int64_t> welded = weldByPosition(mesh.vertices);
  const int64_t n = mesh.triangleCount();
  // Corners t·3 + k in the order of (welded vertex, value); equal neighbours become one vertex.
  auto key = [&](int64_t corner) {
    const Rgb& b = corners[corner / 3][corner % 3];
    return std::make_tuple(welded[mesh.triangles[corner / 3][corner % 3]], b[0], b[1], b[2]);
  };
  std::vector<int64_t> order(3 * n);
  for (int64_t c = 0; c < 3 * n; ++c) order[c] = c;
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
  DisplayMesh out;
  out.triangles.resize(n);
  for (size_t i = 0; i < order.size(); ++i) {
    const int64_t c = order[i];
    if (i == 0 || key(order[i - 1]) != key(c)) {
      out.vertices.push_back(mesh.vertices[mesh.triangles[c / 3][c % 3]]);
      out.radiosity.push_back(corners[c / 3][c % 3]);
    }
    out.triangles[c / 3][c % 3] = static_cast<int64_t>(out.vertices.size()) - 1;
  }
  return out;
}

}  // namespace radiosity
