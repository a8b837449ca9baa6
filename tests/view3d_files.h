// View3D input files (.vs3) for the tests: the manual's unit cube, and the cube cut into n × n
// squares a face, each a surface of its own, whose view factors tests/thermal_scenes.h knows.
#pragma once

#include <array>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "thermal_scenes.h"

namespace radiosity::testing {

/// View3D's own example (its manual, "A simple cube"): six faces numbered and named as there.
inline const char* const kView3dCube =
    "T The unit cube\n"
    "C encl=1 list=3\n"
    "F 3\n"
    "!  #   x    y    z      coordinates of vertices\n"
    "V  1   0.   0.   0.\nV  2   1.   0.   0.\nV  3   1.   1.   0.\nV  4   0.   1.   0.\n"
    "V  5   0.   0.   1.\nV  6   1.   0.   1.\nV  7   1.   1.   1.\nV  8   0.   1.   1.\n"
    "!  #   v1  v2  v3  v4 base cmb  emit  name      surface data\n"
    "S  1    1   2   3   4   0   0   0.50  zeq0\n"
    "S  2    1   4   8   5   0   0   0.50  xeq0\n"
    "S  3    1   5   6   2   0   0   0.50  yeq0\n"
    "S  4    7   6   5   8   0   0   0.50  zeq1\n"
    "S  5    7   3   2   6   0   0   0.50  xeq1\n"
    "S  6    7   8   4   3   0   0   0.50  yeq1\n"
    "End of data\n";

/// The unit cube's exact face factors: opposite faces (Howell C-11), and adjacent ones by
/// the row sum (Σ = 1, four alike).
inline constexpr double kCubeOpposite = 0.199824896, kCubeAdjacent = 0.200043776;

/// The unit cube with n × n squares a face (cubeSquares' order), each a .vs3 surface named
/// "sK" (K its index), facing in; vertices shared.
inline std::string view3dSquares(int n, double emissivity) {
  std::map<std::array<double, 3>, int> ids;
  std::ostringstream vertices, surfaces;
  auto vertex = [&](std::array<double, 3> p) {
    auto [it, added] = ids.emplace(p, static_cast<int>(ids.size()) + 1);
    if (added) vertices << "V " << it->second << ' ' << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    return it->second;
  };
  const std::vector<CubeSquare> squares = cubeSquares(n);
  for (size_t k = 0; k < squares.size(); ++k) {
    const CubeSquare& s = squares[k];
    std::array<int, 4> corner{};
    const double uv[4][2] = {
        {s.lo[0], s.lo[1]}, {s.hi[0], s.lo[1]}, {s.hi[0], s.hi[1]}, {s.lo[0], s.hi[1]}};
    for (int c = 0; c < 4; ++c) {
      std::array<double, 3> p{};
      p[s.axis] = s.position;
      p[s.along[0]] = uv[c][0];
      p[s.along[1]] = uv[c][1];
      corner[c] = vertex(p);
    }
    // (lo, lo) → (hi, lo) → (hi, hi) turns about +axis: in at 0, reversed at 1.
    if (s.position > 0.5) std::swap(corner[1], corner[3]);
    surfaces << "S " << k + 1 << ' ' << corner[0] << ' ' << corner[1] << ' ' << corner[2] << ' '
             << corner[3] << " 0 0 " << emissivity << " s" << k << '\n';
  }
  return "T cube of squares\nC encl=1\nF 3\n" + vertices.str() + surfaces.str() + "E\n";
}

/// A View3D text output file (View3D's layout, which `radiosity export --view-factors` writes):
/// header words, areas, the matrix and the emissivities.
struct View3dOutput {
  std::vector<std::string> header;
  std::vector<double> area, factors, emissivity;
  size_t n = 0;
};
inline View3dOutput readView3dOutput(const std::string& path) {
  std::ifstream in(path);
  View3dOutput out;
  std::string line;
  std::getline(in, line);
  std::istringstream words(line);
  for (std::string w; words >> w;) out.header.push_back(w);
  if (out.header.size() != 6) return out;
  out.n = std::stoul(out.header[5]);
  double v = 0;
  for (size_t k = 0; k < out.n && in >> v; ++k) out.area.push_back(v);
  for (size_t k = 0; k < out.n * out.n && in >> v; ++k) out.factors.push_back(v);
  for (size_t k = 0; k < out.n && in >> v; ++k) out.emissivity.push_back(v);
  return out;
}

}  // namespace radiosity::testing
