// The scenes of the thermal tests (tests/end_to_end_thermal_test.cpp), written as OBJ+MTL with
// a material per surface, and an independent reference for the cube: a dense solve over squares
// with exact rectangle view factors.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "analytic_view_factors.h"

namespace radiosity::testing {

inline constexpr double kSigma = 5.670374419e-8;

// The MTL of the materials named, all grey (a thermal run replaces them).
inline void writeMaterials(const std::string& mtl, const std::vector<std::string>& names) {
  std::ofstream out(mtl);
  for (const std::string& name : names) out << "newmtl " << name << "\nKd 0.5 0.5 0.5\n";
}

// An icosphere of radius 1: `level` times subdivided, its faces counter-clockwise seen from
// outside.
struct Icosphere {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  double area(const std::array<int, 3>& f) const {
    const auto &p = vertices[f[0]], &q = vertices[f[1]], &s = vertices[f[2]];
    const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double w[3] = {s[0] - p[0], s[1] - p[1], s[2] - p[2]};
    return 0.5 * std::sqrt(std::pow(u[1] * w[2] - u[2] * w[1], 2) +
                           std::pow(u[2] * w[0] - u[0] * w[2], 2) +
                           std::pow(u[0] * w[1] - u[1] * w[0], 2));
  }
  double z(const std::array<int, 3>& f) const {  // of its centroid
    return (vertices[f[0]][2] + vertices[f[1]][2] + vertices[f[2]][2]) / 3;
  }
};

inline Icosphere icosphere(int level) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Icosphere s;
  s.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  s.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  auto unit = [](std::array<double, 3> p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<double, 3>{p[0] / n, p[1] / n, p[2] / n};
  };
  for (auto& p : s.vertices) p = unit(p);
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      auto [it, added] = middle.emplace(std::minmax(a, b), static_cast<int>(s.vertices.size()));
      if (added) {
        const auto &p = s.vertices[a], &q = s.vertices[b];
        s.vertices.push_back(unit({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      }
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (auto [a, b, c] : s.faces) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    s.faces = finer;
  }
  return s;
}

// Writes the vertices of `sphere` scaled by each of `radii`, in turn, to `out` (OBJ).
inline void writeVertices(std::ofstream& out, const Icosphere& sphere,
                          const std::vector<double>& radii) {
  out.precision(17);
  for (double r : radii)
    for (const auto& p : sphere.vertices)
      out << "v " << r * p[0] << " " << r * p[1] << " " << r * p[2] << "\n";
}

// Two concentric icospheres (radii 1 and 2), the inner one's normals out, the outer one's in:
// `inner` and `outer`. Returns their areas.
inline std::array<double, 2> writeSpheres(const std::string& obj, int level) {
  const Icosphere sphere = icosphere(level);
  const std::string mtl = obj.substr(0, obj.size() - 4) + ".mtl";
  writeMaterials(mtl, {"inner", "outer"});
  std::ofstream out(obj);
  out << "mtllib " << std::filesystem::path(mtl).filename().string() << "\n";
  writeVertices(out, sphere, {1.0, 2.0});
  const auto n = static_cast<int>(sphere.vertices.size());
  out << "usemtl inner\n";
  for (auto [a, b, c] : sphere.faces) out << "f " << a + 1 << " " << b + 1 << " " << c + 1 << "\n";
  out << "usemtl outer\n";  // wound the other way: lit inside
  for (auto [a, b, c] : sphere.faces)
    out << "f " << n + a + 1 << " " << n + c + 1 << " " << n + b + 1 << "\n";
  double area = 0;
  for (const auto& f : sphere.faces) area += sphere.area(f);
  return {area, 4 * area};
}

// The inside of a unit icosphere in three zones by the height of each facet: `hot` above
// z = 0.5, `cold` below −0.5, `band` between. Returns their areas.
inline std::array<double, 3> writeZonedSphere(const std::string& obj, int level) {
  const Icosphere sphere = icosphere(level);
  const std::string mtl = obj.substr(0, obj.size() - 4) + ".mtl";
  const std::vector<std::string> zones = {"hot", "band", "cold"};
  writeMaterials(mtl, zones);
  std::ofstream out(obj);
  out << "mtllib " << std::filesystem::path(mtl).filename().string() << "\n";
  writeVertices(out, sphere, {1.0});
  std::array<double, 3> area{};
  for (int zone = 0; zone < 3; ++zone) {
    out << "usemtl " << zones[zone] << "\n";
    for (const auto& f : sphere.faces) {
      const double z = sphere.z(f);
      if ((z > 0.5 ? 0 : z < -0.5 ? 2 : 1) != zone) continue;
      out << "f " << f[0] + 1 << " " << f[2] + 1 << " " << f[1] + 1 << "\n";  // lit inside
      area[zone] += sphere.area(f);
    }
  }
  return area;
}

// The unit cube, normals in: `hot` the floor (z = 0), `cold` the ceiling, `sides` the rest.
inline void writeCube(const std::string& obj) {
  const std::string mtl = obj.substr(0, obj.size() - 4) + ".mtl";
  writeMaterials(mtl, {"hot", "cold", "sides"});
  std::ofstream out(obj);
  out << "mtllib " << std::filesystem::path(mtl).filename().string() << "\n"
      << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      << "usemtl hot\nf 1 2 3 4\nusemtl cold\nf 5 8 7 6\n"
      << "usemtl sides\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
}

/// A square of the cube of writeCube, n × n a face.
struct CubeSquare {
  int face, axis;       ///< the face (0 floor, 1 ceiling, 2-5 sides) and its normal's axis
  double position;      ///< of its plane along that axis
  int along[2];         ///< the other two axes
  double lo[2], hi[2];  ///< its extent along them
  std::pair<double, double> range(int onAxis) const {
    const int k = along[0] == onAxis ? 0 : 1;
    return {lo[k], hi[k]};
  }
};

inline std::vector<CubeSquare> cubeSquares(int n) {
  const std::array<std::pair<int, double>, 6> faces = {
      {{2, 0.0}, {2, 1.0}, {0, 0.0}, {0, 1.0}, {1, 0.0}, {1, 1.0}}};
  std::vector<CubeSquare> squares;
  for (int face = 0; face < 6; ++face) {
    const auto [axis, position] = faces[face];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        squares.push_back({face,
                           axis,
                           position,
                           {(axis + 1) % 3, (axis + 2) % 3},
                           {double(i) / n, double(j) / n},
                           {double(i + 1) / n, double(j + 1) / n}});
  }
  return squares;
}

/// The exact view factor from square a to square b of the cube (0 on one face).
inline double squareFactor(const CubeSquare& a, const CubeSquare& b) {
  if (a.face == b.face) return 0;
  if (a.axis == b.axis) {  // opposite faces, one apart
    const auto [x0, x1] = b.range(a.along[0]);
    const auto [y0, y1] = b.range(a.along[1]);
    return parallelRectangles({a.lo[0], a.hi[0], a.lo[1], a.hi[1]}, {x0, x1, y0, y1}, 1.0);
  }
  // Perpendicular: along their common axis, and each one's distances from the other's plane.
  auto distances = [](std::pair<double, double> extent, double plane) {
    const double p = std::abs(extent.first - plane), q = std::abs(extent.second - plane);
    return std::pair{std::min(p, q), std::max(p, q)};
  };
  const int common = 3 - a.axis - b.axis;
  Rectangle r{}, s{};
  std::tie(r.x0, r.x1) = a.range(common);
  std::tie(s.x0, s.x1) = b.range(common);
  std::tie(r.y0, r.y1) = distances(a.range(b.axis), b.position);
  std::tie(s.y0, s.y1) = distances(b.range(a.axis), a.position);
  return perpendicularRectangles(r, s);
}

/// The hot floor's net heat rate in the cube of writeCube (floor at tHot, ceiling at tCold, the
/// sides adiabatic), by a dense solve over n × n squares a face with exact view factors.
inline double cubeHeatRate(int n, double epsHot, double tHot, double epsCold, double tCold) {
  const std::vector<CubeSquare> squares = cubeSquares(n);
  const size_t count = squares.size();
  std::vector<double> f(count * count), rho(count), e(count), j(count, 0.0);
  for (size_t p = 0; p < count; ++p) {
    for (size_t q = 0; q < count; ++q) f[p * count + q] = squareFactor(squares[p], squares[q]);
    const int face = squares[p].face;
    rho[p] = face == 0 ? 1 - epsHot : face == 1 ? 1 - epsCold : 1.0;
    e[p] = face == 0   ? epsHot * kSigma * std::pow(tHot, 4)
           : face == 1 ? epsCold * kSigma * std::pow(tCold, 4)
                       : 0.0;
  }
  auto irradiance = [&](size_t p) {
    double h = 0;
    for (size_t q = 0; q < count; ++q) h += f[p * count + q] * j[q];
    return h;
  };
  for (int sweep = 0; sweep < 100000; ++sweep) {  // Gauss-Seidel to round-off
    double change = 0, size = 0;
    for (size_t p = 0; p < count; ++p) {
      const double next = e[p] + rho[p] * irradiance(p);
      change = std::max(change, std::abs(next - j[p]));
      size = std::max(size, std::abs(next));
      j[p] = next;
    }
    if (change <= 1e-14 * size) break;
  }
  double rate = 0;
  for (size_t p = 0; p < count; ++p)
    if (squares[p].face == 0) rate += (j[p] - irradiance(p)) / (n * n);
  return rate;
}

}  // namespace radiosity::testing
