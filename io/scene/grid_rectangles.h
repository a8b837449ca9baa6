// Private to io/scene: the builtin scenes made of axis-aligned rectangles (rooms, city), each
// cut into a grid of cells of about one element size and welded into one conforming mesh.
// Built for speed at 10^7 triangles: no allocation per triangle, vertices welded once by sorting.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "core/mesh.h"

namespace radiosity::detail {

/// Up to 7 breakpoints along one axis; each interval between two is tessellated on its own, so
/// two rectangles sharing an interval share its grid nodes exactly.
struct Breaks {
  std::array<double, 7> at{};
  int count = 0;
  Breaks(std::initializer_list<double> values) {
    for (double v : values) at[count++] = v;
  }
  int intervals() const { return count - 1; }
};

/// Cells of about size h along a length: at least one, at most kMostCells.
inline constexpr double kMostCells = 0x1p30;
int64_t cellsAlong(double length, double h);

/// The grid lines of `breaks` at element size h, into `out`.
void gridLines(const Breaks& breaks, double h, std::vector<double>& out);

/// Deterministic uniform numbers in [0, 1) from (seed, item, draw) by SplitMix64: the same
/// scene on every rank and machine (the standard distributions' output is implementation-defined).
double splitMixUniform(uint64_t seed, uint64_t item, uint64_t draw);

/// A rectangle type R has: `int axis; double c; Breaks u, v; int facing;` (at coordinate c on
/// `axis`, spanning axes axis + 1 and axis + 2 mod 3 over the breakpoints u and v, lit on the
/// side `facing` = ±1 of `axis`) and `bool skipped(int i, int j) const` (breakpoint cell (i, j)
/// is a hole).
/// Their triangles at element size h (summed in double, exact below 2^53, so that a count past
/// int64 saturates at 2^62 rather than wrapping).
template <class R>
int64_t triangleCount(const std::vector<R>& rects, double h) {
  double count = 0;
  for (const R& r : rects) {
    for (int i = 0; i < r.u.intervals(); ++i) {
      const auto nu = static_cast<double>(cellsAlong(r.u.at[i + 1] - r.u.at[i], h));
      for (int j = 0; j < r.v.intervals(); ++j) {
        if (!r.skipped(i, j))
          count += 2 * nu * static_cast<double>(cellsAlong(r.v.at[j + 1] - r.v.at[j], h));
      }
    }
  }
  return static_cast<int64_t>(std::min(count, 0x1p62));
}

/// Appends rectangle r's grid nodes to `raw` and calls emit(Triangle) for its two triangles per
/// cell (indices into `raw`), counter-clockwise seen from the lit side. `us`, `vs`: reused memory.
template <class R, class Emit>
void tessellateRectangle(const R& r, double h, std::vector<Vec3>& raw, std::vector<double>& us,
                         std::vector<double>& vs, Emit emit) {
  gridLines(r.u, h, us);
  gridLines(r.v, h, vs);
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
  // Cell (i, j) lies in breakpoint interval (bi, bj); the holes are whole intervals.
  int bj = 0;
  for (int64_t j = 0; j + 1 < static_cast<int64_t>(vs.size()); ++j) {
    while (vs[j] >= r.v.at[bj + 1]) ++bj;
    int bi = 0;
    for (int64_t i = 0; i + 1 < width; ++i) {
      while (us[i] >= r.u.at[bi + 1]) ++bi;
      if (r.skipped(bi, bj)) continue;
      const int64_t p00 = base + j * width + i, p10 = p00 + 1, p01 = p00 + width, p11 = p01 + 1;
      // e_a1 × e_a2 = e_axis: counter-clockwise in (u, v) faces +axis.
      emit(r.facing > 0 ? Triangle{p00, p10, p11} : Triangle{p00, p11, p10});
      emit(r.facing > 0 ? Triangle{p00, p11, p01} : Triangle{p00, p01, p11});
    }
  }
}

/// Welds `raw` (equal coordinates → one vertex) into mesh.vertices, numbered in order of first
/// use by mesh.triangles, whose corners index `raw` on entry and mesh.vertices on return.
void weldVertices(const std::vector<Vec3>& raw, Mesh& mesh);

/// What a rectangle's triangles carry.
struct RectangleSurface {
  int64_t sourceFace;
  Rgb reflectance, emission;
  int32_t label;
};

/// Every rectangle tessellated at element size h and welded into one mesh; surfaceOf(index,
/// rectangle) says what its triangles carry. Labels are set, their names left to the caller.
template <class R, class SurfaceOf>
Mesh tessellateRectangles(const std::vector<R>& rects, double h, SurfaceOf surfaceOf) {
  const int64_t triangles = triangleCount(rects, h);
  Mesh mesh;
  mesh.triangles.reserve(triangles);
  mesh.sourceFace.reserve(triangles);
  mesh.reflectance.reserve(triangles);
  mesh.emission.reserve(triangles);
  mesh.label.reserve(triangles);
  std::vector<Vec3> raw;
  raw.reserve(triangles / 2 + triangles / 8 + 1024);
  std::vector<double> us, vs;  // grid lines of the current rectangle
  for (size_t f = 0; f < rects.size(); ++f) {
    const RectangleSurface surface = surfaceOf(f, rects[f]);
    tessellateRectangle(rects[f], h, raw, us, vs, [&](const Triangle& t) {
      mesh.triangles.push_back(t);
      mesh.sourceFace.push_back(surface.sourceFace);
      mesh.reflectance.push_back(surface.reflectance);
      mesh.emission.push_back(surface.emission);
      mesh.label.push_back(surface.label);
    });
  }
  weldVertices(raw, mesh);
  return mesh;
}

}  // namespace radiosity::detail
