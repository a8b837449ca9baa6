// builtin:cornell: the Cornell box as measured, its floor cut around the blocks' footprints and
// its ceiling around the light, so that no patch reaches where light cannot.
#include "io/scene/builtin_cornell.h"

#include <algorithm>
#include <array>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace radiosity::detail {
namespace {

/// The floor y = 0 of the Cornell box with the blocks' footprints cut out, as convex pieces: the
/// floor under a block is never lit, and a patch that reached under one would spread that
/// darkness over its lit part (the light beside the blocks' feet came out low, as `radiosity
/// verify` showed). Cut in slabs z ∈ [z_k, z_k+1] at every corner's z, where each
/// boundary (the floor's sides, the footprints' sides) is a straight line in x, so each slab
/// splits into quads.
void cornellFloor(SceneBuilder& b, const std::vector<Vec3>& floor,
                  const std::vector<std::vector<Vec3>>& holes, const Rgb& rho) {
  // x-interval of a convex polygon on the line z = at, if it meets it.
  auto across = [](const std::vector<Vec3>& polygon, double at) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t k = 0; k < polygon.size(); ++k) {
      const Vec3 a = polygon[k], c = polygon[(k + 1) % polygon.size()];
      if ((a.z - at) * (c.z - at) > 0) continue;
      const double x = a.z == c.z ? a.x : a.x + (c.x - a.x) * (at - a.z) / (c.z - a.z);
      const double x2 = a.z == c.z ? c.x : x;
      lo = std::min({lo, x, x2}), hi = std::max({hi, x, x2});
    }
    return std::pair{lo, hi};
  };
  std::vector<double> zs;
  for (const Vec3& v : floor) zs.push_back(v.z);
  for (const auto& hole : holes)
    for (const Vec3& v : hole) zs.push_back(v.z);
  std::sort(zs.begin(), zs.end());
  zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
  for (size_t k = 0; k + 1 < zs.size(); ++k) {
    const double za = zs[k], zb = zs[k + 1], middle = (za + zb) / 2;
    // The boundaries inside the slab, left to right, each as its x at za and zb.
    std::vector<std::array<double, 2>> left, right;
    const auto [fa, fa2] = across(floor, za);
    const auto [fb, fb2] = across(floor, zb);
    left.push_back({fa, fb});
    std::vector<std::pair<double, size_t>> order;
    for (size_t h = 0; h < holes.size(); ++h) {
      const auto [lo, hi] = across(holes[h], middle);
      if (lo <= hi) order.emplace_back(lo, h);
    }
    std::sort(order.begin(), order.end());
    for (const auto& [unused, h] : order) {
      const auto [la, ha] = across(holes[h], za);
      const auto [lb, hb] = across(holes[h], zb);
      right.push_back({la, lb});
      left.push_back({ha, hb});
    }
    right.push_back({fa2, fb2});
    for (size_t piece = 0; piece < left.size(); ++piece) {
      std::vector<Vec3> corners = {{left[piece][0], 0, za},
                                   {left[piece][1], 0, zb},
                                   {right[piece][1], 0, zb},
                                   {right[piece][0], 0, za}};
      auto same = [](const Vec3& u, const Vec3& v) { return u.x == v.x && u.z == v.z; };
      corners.erase(std::unique(corners.begin(), corners.end(), same), corners.end());
      if (corners.size() > 3 && same(corners.back(), corners.front())) corners.pop_back();
      if (corners.size() >= 3) b.addPolygon(corners, {0, 1, 0}, rho, {0, 0, 0});
    }
  }
}

/// A block as the Cornell data give it: its footprint (x, z) on the floor, its height, and the
/// order in which the data list its sides. Its top is the footprint in reverse; side i rises from
/// the footprint's edge from corner i to corner i + 1.
struct Block {
  const char* label;
  std::array<std::array<double, 2>, 4> footprint;
  double height;
  std::array<int, 4> sides;
};

constexpr Block kBlocks[] = {
    {"short block", {{{130, 65}, {290, 114}, {240, 272}, {82, 225}}}, 165, {1, 0, 3, 2}},
    {"tall block", {{{423, 247}, {472, 406}, {314, 456}, {265, 296}}}, 330, {0, 1, 2, 3}},
};

Vec3 at(const std::array<double, 2>& xz, double y) { return {xz[0], y, xz[1]}; }

/// Where `block` stands: a hole in the floor.
std::vector<Vec3> footprintOf(const Block& block) {
  std::vector<Vec3> corners;
  for (const auto& xz : block.footprint) corners.push_back(at(xz, 0));
  return corners;
}

/// The faces of `block` in the data's order: its top, then its sides (its bottom is unseen).
std::vector<std::vector<Vec3>> facesOf(const Block& block) {
  const auto& f = block.footprint;
  const double h = block.height;
  std::vector<std::vector<Vec3>> faces = {{at(f[0], h), at(f[3], h), at(f[2], h), at(f[1], h)}};
  for (int i : block.sides) {
    const auto &from = f[i], &to = f[(i + 1) % 4];
    faces.push_back({at(from, 0), at(from, h), at(to, h), at(to, 0)});
  }
  return faces;
}

}  // namespace

/// The Cornell box as measured (Cornell University Program of Computer Graphics, "Cornell Box
/// Data"), in mm. Source faces: 0 floor; 1–9 ceiling cells, row by row in z then x, cell 5 being
/// the light; 10 back wall; 11 right wall (green, x = 0); 12 left wall (red); 13 short block top,
/// 14–17 its sides; 18 tall block top, 19–22 its sides. Block bottoms are left out (unseen).
/// `scale` multiplies every coordinate (1: mm). `cut_floor` 0 gives the floor as published, one
/// quad running under the blocks (source face 0 still), as users' copies of the data have it.
Mesh cornell(const Params& p) {
  const Rgb white = {0.725, 0.71, 0.68}, red = {0.63, 0.065, 0.05}, green = {0.14, 0.45, 0.091};
  const double pi = std::numbers::pi;
  const Rgb light = {pi * 17 * p.at("light"), pi * 12 * p.at("light"), pi * 4 * p.at("light")};
  const Rgb none = {0, 0, 0};
  const Vec3 boxCentre = {278, 274, 280};
  SceneBuilder b;
  auto wall = [&](std::vector<Vec3> q, const Rgb& rho, const Rgb& e) {
    const Vec3 inward = boxCentre - centroid(q);
    b.addPolygon(std::move(q), inward, rho, e);
  };
  b.setLabel("floor");
  const std::vector<Vec3> floor = {{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}};
  if (p.at("cut_floor") != 0) {
    cornellFloor(b, floor, {footprintOf(kBlocks[0]), footprintOf(kBlocks[1])}, white);
  } else {
    b.addPolygon(floor, {0, 1, 0}, white, {0, 0, 0});  // as published: one quad under the blocks
  }
  // The ceiling is rectangular; cutting it at the light's edges keeps the mesh conforming
  // instead of overlapping the light with the ceiling.
  const double xs[] = {0, 213, 343, 556}, zs[] = {0, 227, 332, 559.2}, y = 548.8;
  for (int iz = 0; iz < 3; ++iz) {
    for (int ix = 0; ix < 3; ++ix) {
      const bool isLight = ix == 1 && iz == 1;
      b.setLabel(isLight ? "light" : "ceiling");
      wall({{xs[ix], y, zs[iz]},
            {xs[ix + 1], y, zs[iz]},
            {xs[ix + 1], y, zs[iz + 1]},
            {xs[ix], y, zs[iz + 1]}},
           white, isLight ? light : none);
    }
  }
  b.setLabel("back wall");
  wall({{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}, white, none);
  b.setLabel("green wall");
  wall({{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}, green, none);
  b.setLabel("red wall");
  wall({{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}, red, none);

  auto block = [&](const std::vector<std::vector<Vec3>>& faces) {
    std::vector<Vec3> all;
    for (const auto& f : faces) all.insert(all.end(), f.begin(), f.end());
    const Vec3 centre = centroid(all);
    for (const auto& f : faces) b.addPolygon(f, centroid(f) - centre, white, none);
  };
  for (const Block& k : kBlocks) {
    b.setLabel(k.label);
    block(facesOf(k));
  }
  // Scaled once built, so that the welding and triangulation above are the same at any scale.
  Mesh mesh = b.take();
  for (Vec3& v : mesh.vertices) v = p.at("scale") * v;
  if (p.at("scale") == 1) mesh.lengthUnit = "mm";
  return mesh;
}

}  // namespace radiosity::detail
