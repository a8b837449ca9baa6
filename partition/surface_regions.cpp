// Regions of a mesh joined along shared edges (surface_regions.h): a union-find over the edges
// sorted by their ends' positions.
#include "partition/surface_regions.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "partition/contact_finder.h"

namespace radiosity::partition {

namespace {

int64_t root(std::vector<int64_t>& parent, int64_t t) {
  while (parent[t] != t) t = parent[t] = parent[parent[t]];
  return t;
}

}  // namespace

std::vector<double> regionAreas(const Mesh& mesh,
                                const std::function<bool(int64_t s, int64_t t)>& joined,
                                int64_t* regions,
                                const std::vector<std::array<int64_t, 2>>* apart) {
  const int64_t n = mesh.triangleCount();
  const std::vector<int64_t> position = contacts::positionIds(mesh);
  // (edge's two position ids, triangle), sorted: triangles sharing an edge come together.
  std::vector<std::pair<std::array<int64_t, 2>, int64_t>> edges;
  edges.reserve(3 * n);
  for (int64_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = position[mesh.triangles[t][k]],
                    b = position[mesh.triangles[t][(k + 1) % 3]];
      edges.push_back({{std::min(a, b), std::max(a, b)}, t});
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::array<int64_t, 2>> separating;  // `apart` by position
  if (apart)
    for (const auto& [a, b] : *apart)
      separating.push_back(
          {std::min(position[a], position[b]), std::max(position[a], position[b])});
  std::sort(separating.begin(), separating.end());
  std::vector<int64_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0, j = 0; i < edges.size(); i = j) {
    for (j = i + 1; j < edges.size() && edges[j].first == edges[i].first;) ++j;
    if (std::binary_search(separating.begin(), separating.end(), edges[i].first)) continue;
    for (size_t k = i + 1; k < j; ++k)
      if (joined(edges[i].second, edges[k].second))
        parent[root(parent, edges[i].second)] = root(parent, edges[k].second);
  }
  std::vector<double> regionArea(n, 0.0);
  for (int64_t t = 0; t < n; ++t) regionArea[root(parent, t)] += mesh.area(t);
  std::vector<double> area(n);
  for (int64_t t = 0; t < n; ++t) area[t] = regionArea[root(parent, t)];
  if (regions) {
    *regions = 0;
    for (int64_t t = 0; t < n; ++t) *regions += root(parent, t) == t;
  }
  return area;
}

std::vector<double> smoothSurfaceAreas(const Mesh& mesh, int64_t* surfaces,
                                       const std::vector<std::array<int64_t, 2>>* contactEdges) {
  return regionAreas(
      mesh,
      [&](int64_t s, int64_t t) {
        return dot(mesh.normal(s), mesh.normal(t)) > contacts::kCreaseCosine;
      },
      surfaces, contactEdges);
}

}  // namespace radiosity::partition
