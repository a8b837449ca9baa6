// builtin:city: box buildings on a ground plane, open to the sky: the open, occluded case the
// enclosures (box, sphere, Cornell box, rooms) do not cover, for sky view factors and
// building-to-building view factors. Every surface is an axis-aligned rectangle tessellated into
// a grid of cells of about the element size, so the element size sets the triangle count.
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "io/core/error.h"
#include "io/scene/scene_builder.h"
#include "io/scene/scene_internal.h"

namespace radiosity::detail {
namespace {

/// More triangles than this are refused: the element size was surely mistyped.
constexpr int64_t kMaxTriangles = 100'000'000;

/// Up to 4 breakpoints along one axis; each interval is tessellated on its own, so two
/// rectangles sharing an interval (a wall's foot and the ground beside it) share its nodes.
struct Breaks {
  std::array<double, 4> at{};
  int count = 0;
  Breaks(std::initializer_list<double> values) {
    for (double v : values) at[count++] = v;
  }
  int intervals() const { return count - 1; }
};

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
};

/// One building: its footprint [x0, x1] × [z0, z1] and height.
struct Building {
  double x0, x1, z0, z1, height;
};

int64_t cellsAlong(double length, double h) {
  return std::max<int64_t>(1, std::llround(length / h));
}

int64_t triangleCount(const std::vector<Rect>& rects, double h) {
  int64_t count = 0;
  for (const Rect& r : rects) {
    for (int i = 0; i < r.u.intervals(); ++i) {
      const int64_t nu = cellsAlong(r.u.at[i + 1] - r.u.at[i], h);
      for (int j = 0; j < r.v.intervals(); ++j) {
        if (i != r.holeU || j != r.holeV)
          count += 2 * nu * cellsAlong(r.v.at[j + 1] - r.v.at[j], h);
      }
    }
  }
  return count;
}

/// Deterministic uniform numbers in [0, 1) from (seed, building, draw): SplitMix64, so that the
/// same seed gives the same city on every rank and machine (the standard distributions' output
/// is implementation-defined).
double uniform(uint64_t seed, uint64_t building, uint64_t draw) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ULL + building * 0xBF58476D1CE4E5B9ULL + draw + 1;
  for (int k = 0; k < 2; ++k) {
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
  }
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

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

/// Tessellates every rectangle into an h-grid, welding equal vertices by sorting (as rooms do).
Mesh tessellate(const std::vector<Rect>& rects, double h, int buildings, const CityMaterials& m) {
  const int64_t triangles = triangleCount(rects, h);
  Mesh mesh;
  mesh.triangles.reserve(triangles);
  mesh.sourceFace.reserve(triangles);
  mesh.reflectance.reserve(triangles);
  mesh.emission.reserve(triangles);
  mesh.label.reserve(triangles);
  mesh.labelNames.emplace_back("ground");
  for (int k = 1; k <= buildings; ++k) mesh.labelNames.push_back("building " + std::to_string(k));
  std::vector<Vec3> raw;

  std::vector<double> us, vs;
  auto lines = [h](const Breaks& b, std::vector<double>& out) {
    out.clear();
    out.push_back(b.at[0]);
    for (int i = 0; i < b.intervals(); ++i) {
      const double a = b.at[i], c = b.at[i + 1];
      const int64_t n = cellsAlong(c - a, h);
      for (int64_t s = 1; s < n; ++s) out.push_back(a + (c - a) * static_cast<double>(s) / n);
      out.push_back(c);
    }
  };
  for (const Rect& r : rects) {
    const bool ground = r.label == 0;
    const Rgb rho = grey(m.rho);
    const Rgb e = grey(ground ? m.eGround : m.eBuilding);
    lines(r.u, us);
    lines(r.v, vs);
    const int a1 = (r.axis + 1) % 3, a2 = (r.axis + 2) % 3;
    const auto base = static_cast<int64_t>(raw.size());
    const auto width = static_cast<int64_t>(us.size());
    for (double v : vs) {
      for (double u : us) {
        Vec3 p;
        p[r.axis] = r.c;
        p[a1] = u;
        p[a2] = v;
        raw.push_back(p);
      }
    }
    int bj = 0;
    for (int64_t j = 0; j + 1 < static_cast<int64_t>(vs.size()); ++j) {
      while (vs[j] >= r.v.at[bj + 1]) ++bj;
      int bi = 0;
      for (int64_t i = 0; i + 1 < width; ++i) {
        while (us[i] >= r.u.at[bi + 1]) ++bi;
        if (bi == r.holeU && bj == r.holeV) continue;
        const int64_t p00 = base + j * width + i, p10 = p00 + 1, p01 = p00 + width, p11 = p01 + 1;
        // e_a1 × e_a2 = e_axis: counter-clockwise in (u, v) faces +axis.
        const Triangle first = r.facing > 0 ? Triangle{p00, p10, p11} : Triangle{p00, p11, p10};
        const Triangle second = r.facing > 0 ? Triangle{p00, p11, p01} : Triangle{p00, p01, p11};
        for (const Triangle& t : {first, second}) {
          mesh.triangles.push_back(t);
          mesh.sourceFace.push_back(r.face);
          mesh.reflectance.push_back(rho);
          mesh.emission.push_back(e);
          mesh.label.push_back(r.label);
        }
      }
    }
  }

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
      const auto draw = [&](int d) { return uniform(city.seed, static_cast<uint64_t>(number), d); };
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
    throw InputError(spec + ": parameter 'element' = " + std::to_string(city.element) + " gives " +
                     std::to_string(triangles) + " triangles (at most " +
                     std::to_string(kMaxTriangles) + ")");
  }
  Mesh mesh = tessellate(rects, city.element, n * n, materials);
  mesh.lengthUnit = std::string("m");  // (a literal assigned here trips GCC 12's -Wrestrict)
  return mesh;
}

}  // namespace radiosity::detail
