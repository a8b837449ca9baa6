#include "io/scene/grid_rectangles.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radiosity::detail {

int64_t cellsAlong(double length, double h) {
  // Saturated: llround of a ratio past int64 (a tiny element size) is unspecified, and came back
  // negative, i.e. one cell: a silently coarse mesh instead of a refusal of its size.
  return std::max<int64_t>(1, std::llround(std::min(length / h, kMostCells)));
}

void gridLines(const Breaks& breaks, double h, std::vector<double>& out) {
  out.clear();
  out.push_back(breaks.at[0]);
  for (int i = 0; i < breaks.intervals(); ++i) {
    const double a = breaks.at[i], c = breaks.at[i + 1];
    const int64_t n = cellsAlong(c - a, h);
    for (int64_t s = 1; s < n; ++s) out.push_back(a + (c - a) * static_cast<double>(s) / n);
    out.push_back(c);
  }
}

double splitMixUniform(uint64_t seed, uint64_t item, uint64_t draw) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ULL + item * 0xBF58476D1CE4E5B9ULL + draw + 1;
  for (int k = 0; k < 2; ++k) {
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
  }
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

void weldVertices(const std::vector<Vec3>& raw, Mesh& mesh) {
  // Sort the raw vertices by position (ties by index), map each to the first of its group, then
  // number the groups in order of first use by a triangle.
  std::vector<int64_t> order(raw.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
    const Vec3 &p = raw[a], &q = raw[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  });
  std::vector<int64_t> id(raw.size(), -1);  // raw vertex → representative
  for (size_t s = 0; s < order.size(); ++s) {
    id[order[s]] = s > 0 && raw[order[s]] == raw[order[s - 1]] ? id[order[s - 1]] : order[s];
  }
  std::vector<int64_t>& finalId = order;  // reused: representative → final id
  std::fill(finalId.begin(), finalId.end(), -1);
  mesh.vertices.clear();
  mesh.vertices.reserve(raw.size() / 2);
  for (Triangle& t : mesh.triangles) {
    for (int64_t& corner : t) {
      const int64_t rep = id[corner];
      if (finalId[rep] < 0) {
        finalId[rep] = static_cast<int64_t>(mesh.vertices.size());
        mesh.vertices.push_back(raw[rep]);
      }
      corner = finalId[rep];
    }
  }
  mesh.vertices.shrink_to_fit();
}

}  // namespace radiosity::detail
