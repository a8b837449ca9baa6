// builtin:city: box buildings on a ground plane, open to the sky: the open, occluded case the
// enclosures (box, sphere, Cornell box, rooms) do not cover, for sky view factors and
// building-to-building view factors. Every surface is an axis-aligned rectangle tessellated into
// a grid of cells of about the element size, so the element size sets the triangle count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/scene/grid_rectangles.h"
#include "io/scene/scene_builder.h"
#include "io/scene/scene_internal.h"

namespace radiosity::detail {
namespace {

/// More triangles than this are refused: the element size was surely mistyped.
constexpr int64_t kMaxTriangles = 100'000'000;

/// An axis-aligned rectangle at coordinate `c` on axis `axis`, spanning axes a1 = axis + 1 and
/// a2 = axis + 2 (mod 3) over the breakpoints u and v, lit on the side `facing` (+1 or −1) of
/// `axis`. Cell (holeU, holeV) of the breakpoint grid is a hole (a building's footprint).
struct Rect {
  int axis;
  double c;
  Breaks u, v;
  int facing;
  int64_t face;   ///< source face
  int32_t label;  ///< 0 ground, k building k
  int holeU = -1, holeV = -1;
  bool skipped(int i, int j) const { return i == holeU && j == holeV; }
};

/// One building: its footprint [x0, x1] × [z0, z1] and height.
struct Building {
  double x0, x1, z0, z1, height;
};

double between(double lo, double hi, double u) { return lo + (hi - lo) * u; }

/// Roof first, then the walls at x0, x1, z0, z1: source faces 5k − 4 … 5k for building k.
void addBuilding(std::vector<Rect>& rects, const Building& b, int32_t k) {
  const double h = b.height;
  const int64_t f = 5 * int64_t{k} - 4;
  rects.push_back({1, h, {b.z0, b.z1}, {b.x0, b.x1}, +1, f, k});
  rects.push_back({0, b.x0, {0, h}, {b.z0, b.z1}, -1, f + 1, k});
  rects.push_back({0, b.x1, {0, h}, {b.z0, b.z1}, +1, f + 2, k});
  rects.push_back({2, b.z0, {b.x0, b.x1}, {0, h}, -1, f + 3, k});
  rects.push_back({2, b.z1, {b.x0, b.x1}, {0, h}, +1, f + 4, k});
}

/// Tessellates every rectangle into an h-grid, welded into one mesh (grid_rectangles.h).
Mesh tessellate(const std::vector<Rect>& rects, double h, int buildings, const CityMaterials& m) {
  Mesh mesh = tessellateRectangles(rects, h, [&](size_t, const Rect& r) {
    return RectangleSurface{r.face, grey(m.rho), grey(r.label == 0 ? m.eGround : m.eBuilding),
                            r.label};
  });
  mesh.labelNames.emplace_back("ground");
  for (int k = 1; k <= buildings; ++k) mesh.labelNames.push_back("building " + std::to_string(k));
  return mesh;
}

}  // namespace

Mesh buildCity(const CityLayout& city, const CityMaterials& materials, const std::string& spec) {
  if (city.footprintMin > city.footprintMax) {
    throw InputError(spec + ": parameter 'footprint_min' exceeds 'footprint_max'");
  }
  if (city.heightMin > city.heightMax) {
    throw InputError(spec + ": parameter 'height_min' exceeds 'height_max'");
  }
  // Lots of pitch footprint_max + street, each building centred in its own, so that streets
  // are at least `street` wide; the ground reaches half a street beyond the outer lots, so
  // every building has at least a street's width of ground around it.
  const int n = city.perSide;
  const double pitch = city.footprintMax + city.street, side = n * pitch + city.street;
  auto lotEdge = [&](int i) { return i == 0 ? 0.0 : i == n ? side : city.street / 2 + i * pitch; };
  std::vector<Rect> rects;
  rects.reserve(static_cast<size_t>(n) * n * 6);
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      const auto number = static_cast<int32_t>(k * n + i + 1);
      const auto draw = [&](int d) {
        return splitMixUniform(city.seed, static_cast<uint64_t>(number), d);
      };
      const double width = between(city.footprintMin, city.footprintMax, draw(0));
      const double depth = between(city.footprintMin, city.footprintMax, draw(1));
      const double height = between(city.heightMin, city.heightMax, draw(2));
      const double cx = city.street / 2 + (i + 0.5) * pitch,
                   cz = city.street / 2 + (k + 0.5) * pitch;
      const Building b{cx - width / 2, cx + width / 2, cz - depth / 2, cz + depth / 2, height};
      // The ground of this lot, its footprint a hole; its grid lines meet the walls' feet. (Lots
      // side by side split their common edge differently: T-junctions on the ground only.)
      Rect lot{1,
               0,
               {lotEdge(k), b.z0, b.z1, lotEdge(k + 1)},
               {lotEdge(i), b.x0, b.x1, lotEdge(i + 1)},
               +1,
               0,
               0};
      lot.holeU = 1, lot.holeV = 1;
      rects.push_back(lot);
      addBuilding(rects, b, number);
    }
  }
  const int64_t triangles = triangleCount(rects, city.element);
  if (triangles > kMaxTriangles) {
    char element[32];
    std::snprintf(element, sizeof element, "%g", city.element);
    throw InputError(spec + ": parameter 'element' = " + element + " gives " +
                     (triangles >= (int64_t{1} << 62) ? std::string("more than 4.6e18")
                                                      : std::to_string(triangles)) +
                     " triangles (at most " + std::to_string(kMaxTriangles) + ")");
  }
  Mesh mesh = tessellate(rects, city.element, n * n, materials);
  mesh.lengthUnit = std::string("m");  // (a literal assigned here trips GCC 12's -Wrestrict)
  return mesh;
}

}  // namespace radiosity::detail
