// The scene of the renderer's tests (render_test.cpp, render_outputs_test.cpp): the box [0,1]³
// as a result with a radiosity (and irradiance) per wall.
#pragma once

#include <array>
#include <utility>

#include "core/mesh.h"
#include "io/store/result.h"

namespace radiosity::testing {

// The walls of the box [0,1]³, in this order, each two triangles facing inwards.
enum Wall { kX0, kX1, kY0, kY1, kZ0, kZ1 };

// A closed box with eight shared vertices, every wall lit from inside with radiosity wallB and
// irradiance wallH.
inline Result makeBox(const std::array<Rgb, 6>& wallB, const std::array<Rgb, 6>& wallH = {}) {
  Result result;
  Mesh& mesh = result.mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  for (int wall = 0; wall < 6; ++wall) {
    int a = wall / 2, side = wall % 2, b = (a + 1) % 3, c = (a + 2) % 3;
    auto vertex = [&](int pb, int pc) -> int64_t { return (side << a) | (pb << b) | (pc << c); };
    std::array<Triangle, 2> quad = {Triangle{vertex(0, 0), vertex(1, 0), vertex(1, 1)},
                                    Triangle{vertex(0, 0), vertex(1, 1), vertex(0, 1)}};
    Vec3 inward{};
    inward[a] = side == 0 ? 1 : -1;
    for (Triangle t : quad) {
      mesh.triangles.push_back(t);
      if (dot(mesh.normal(mesh.triangleCount() - 1), inward) < 0) {
        std::swap(t[1], t[2]);
        mesh.triangles.back() = t;
      }
      mesh.sourceFace.push_back(mesh.triangleCount() - 1);
      mesh.reflectance.push_back({0.5, 0.5, 0.5});
      mesh.emission.push_back({0, 0, 0});
      result.radiosity.push_back(wallB[wall]);
      result.irradiance.push_back(wallH[wall]);
      result.rank.push_back(0);
    }
  }
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    result.area.push_back(mesh.area(t));
    result.normal.push_back(mesh.normal(t));
  }
  return result;
}

inline Result makeGreyBox(std::array<double, 6> wallB) {
  std::array<Rgb, 6> rgb;
  for (int w = 0; w < 6; ++w) rgb[w] = {wallB[w], wallB[w], wallB[w]};
  return makeBox(rgb);
}

}  // namespace radiosity::testing
