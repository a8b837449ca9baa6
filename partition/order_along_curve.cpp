// Morton (Z-order) numbering of the patches: near ids are near in space, so a rank's block of
// rows mostly references its own columns and each matrix-vector product communicates little.
#include <algorithm>
#include <numeric>
#include <type_traits>

#include "partition/partition.h"

namespace radiosity::partition {

namespace {

// Spreads the low 21 bits of x so that two zero bits separate each.
uint64_t spreadBits(uint64_t x) {
  x &= 0x1FFFFF;
  x = (x | x << 32) & 0x1F00000000FFFFULL;
  x = (x | x << 16) & 0x1F0000FF0000FFULL;
  x = (x | x << 8) & 0x100F00F00F00F00FULL;
  x = (x | x << 4) & 0x10C30C30C30C30C3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

std::vector<uint64_t> curveKeys(const Mesh& patches) {
  const int64_t n = patches.triangleCount();
  Vec3 lo, hi;
  patches.boundingBox(lo, hi);
  std::vector<uint64_t> code(n);
  // One scale for the three axes, the largest extent: each its own would make a flat scene's
  // short axis (a building's height) weigh as much as its plan, and the key's first bits would
  // cut every room into slabs whose rays land in the other slabs (a far larger halo:
  // docs/scaling-model.md).
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  for (int64_t t = 0; t < n; ++t) {
    Vec3 c = patches.centroid(t);
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      double unit = extent > 0 ? (c[k] - lo[k]) / extent : 0.0;
      auto cell = static_cast<uint64_t>(std::clamp(unit, 0.0, 1.0) * 2097151.0);
      key |= spreadBits(cell) << k;
    }
    code[t] = key;
  }
  return code;
}

Mesh orderAlongCurve(Mesh patches) {
  const int64_t n = patches.triangleCount();
  const std::vector<uint64_t> code = curveKeys(patches);
  std::vector<int64_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return code[a] < code[b]; });

  // Permute one per-triangle array at a time: the peak is the mesh plus one array, not two
  // meshes (this matters at 10^7 patches).
  auto permute = [&](auto& field) {
    if (field.empty()) return;
    std::remove_reference_t<decltype(field)> sorted;
    sorted.reserve(n);
    for (int64_t t : order) sorted.push_back(field[t]);
    field = std::move(sorted);
  };
  permute(patches.triangles);
  permute(patches.sourceFace);
  permute(patches.reflectance);
  permute(patches.emission);
  if (patches.hasLabels()) permute(patches.label);
  return patches;
}
}  // namespace radiosity::partition
