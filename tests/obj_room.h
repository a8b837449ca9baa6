// A room as people write one in OBJ (quads, an MTL of named materials), for the end-to-end tests
// that need a scene of their own: a 4 × 3 × 4 m box of white floor, ceiling and walls, one wall
// red and one green, and whatever quads a test adds (a lamp, a table, a block on the floor).
#pragma once

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace radiosity::testing {

struct ObjQuad {
  const char* material;
  std::array<std::array<double, 3>, 4> corners;  ///< counter-clockwise seen from the lit side
};

/// Writes `obj` (the room's walls, then `extra`) and `mtl` (white, red and green, then
/// `materials`: MTL statements of the extra quads' materials).
inline void writeRoomObj(const std::string& obj, const std::string& mtl,
                         const std::string& materials, const std::vector<ObjQuad>& extra) {
  std::ofstream(mtl) << "newmtl white\nKd 0.7 0.7 0.7\nnewmtl red\nKd 0.6 0.1 0.1\n"
                        "newmtl green\nKd 0.1 0.6 0.1\n"
                     << materials;
  std::vector<ObjQuad> quads = {
      {"white", {{{0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}}}},  // floor
      {"white", {{{0, 3, 0}, {4, 3, 0}, {4, 3, 4}, {0, 3, 4}}}},  // ceiling
      {"white", {{{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}}},
      {"white", {{{0, 0, 4}, {0, 3, 4}, {4, 3, 4}, {4, 0, 4}}}},
      {"red", {{{0, 0, 0}, {0, 3, 0}, {0, 3, 4}, {0, 0, 4}}}},
      {"green", {{{4, 0, 0}, {4, 0, 4}, {4, 3, 4}, {4, 3, 0}}}}};
  quads.insert(quads.end(), extra.begin(), extra.end());
  std::ofstream out(obj);
  out << "mtllib " << std::filesystem::path(mtl).filename().string() << "\n";
  int vertices = 0;
  for (const ObjQuad& quad : quads) {
    out << "usemtl " << quad.material << "\n";
    for (const auto& c : quad.corners) out << "v " << c[0] << " " << c[1] << " " << c[2] << "\n";
    out << "f " << vertices + 1 << " " << vertices + 2 << " " << vertices + 3 << " " << vertices + 4
        << "\n";
    vertices += 4;
  }
}

}  // namespace radiosity::testing
