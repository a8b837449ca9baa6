// Small meshes built in code, so that stage tests do not depend on the loaders.
#pragma once

#include "core/mesh.h"

namespace radiosity::testing {

/// Adds the quad a, b, c, d (counter-clockwise seen from its lit side) as two triangles.
inline void addQuad(Mesh& mesh, Vec3 a, Vec3 b, Vec3 c, Vec3 d, Rgb rho, Rgb e) {
  auto base = static_cast<int64_t>(mesh.vertices.size());
  for (Vec3 v : {a, b, c, d}) mesh.vertices.push_back(v);
  int64_t face = mesh.sourceFace.empty() ? 0 : mesh.sourceFace.back() + 1;
  for (Triangle t : {Triangle{base, base + 1, base + 2}, Triangle{base, base + 2, base + 3}}) {
    mesh.triangles.push_back(t);
    mesh.sourceFace.push_back(face);
    mesh.reflectance.push_back(rho);
    mesh.emission.push_back(e);
  }
}

/// Adds the quad a, b, c, d (a parallelogram, counter-clockwise seen from its lit side) as
/// n × n smaller quads of one source face, two triangles each.
inline void addSubdividedQuad(Mesh& mesh, Vec3 a, Vec3 b, Vec3 d, int n, Rgb rho, Rgb e) {
  const auto base = static_cast<int64_t>(mesh.vertices.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i)
      mesh.vertices.push_back(a + (double(i) / n) * (b - a) + (double(j) / n) * (d - a));
  }
  const int64_t face = mesh.sourceFace.empty() ? 0 : mesh.sourceFace.back() + 1;
  auto at = [&](int i, int j) { return base + j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      for (Triangle t : {Triangle{at(i, j), at(i + 1, j), at(i + 1, j + 1)},
                         Triangle{at(i, j), at(i + 1, j + 1), at(i, j + 1)}}) {
        mesh.triangles.push_back(t);
        mesh.sourceFace.push_back(face);
        mesh.reflectance.push_back(rho);
        mesh.emission.push_back(e);
      }
    }
  }
}

/// The unit cube with normals pointing in; 8 shared vertices, 12 triangles.
inline Mesh closedBox(double rho, double e, double size = 1.0) {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.push_back({size * (i & 1), size * ((i >> 1) & 1), size * ((i >> 2) & 1)});
  }
  // Faces as corner indices, counter-clockwise seen from inside the box.
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (int f = 0; f < 6; ++f) {
    for (Triangle t : {Triangle{faces[f][0], faces[f][1], faces[f][2]},
                       Triangle{faces[f][0], faces[f][2], faces[f][3]}}) {
      mesh.triangles.push_back(t);
      mesh.sourceFace.push_back(f);
      mesh.reflectance.push_back({rho, rho, rho});
      mesh.emission.push_back({e, e, e});
    }
  }
  return mesh;
}

/// Two parallel w×h rectangles at distance d facing each other; the one at z = 0 emits.
inline Mesh parallelPlates(double w, double h, double d) {
  Mesh mesh;
  addQuad(mesh, {0, 0, 0}, {w, 0, 0}, {w, h, 0}, {0, h, 0}, {0, 0, 0}, {1, 1, 1});
  addQuad(mesh, {0, 0, d}, {0, h, d}, {w, h, d}, {w, 0, d}, {0, 0, 0}, {0, 0, 0});
  return mesh;
}

/// A thin two-sided quad as modellers write one: the quad a, b, c, d (counter-clockwise seen
/// from its lit side) and, coincident with it, the same quad facing the other way (d, c, b, a
/// seen from the other side), each two triangles with the same diagonal and its own source
/// face. With `shareVertices` the back quad reuses the front quad's vertices, otherwise it gets
/// copies at the same positions.
inline void addTwoSidedQuad(Mesh& mesh, Vec3 a, Vec3 b, Vec3 c, Vec3 d, Rgb rho, Rgb e,
                            bool shareVertices) {
  const auto front = static_cast<int64_t>(mesh.vertices.size());
  addQuad(mesh, a, b, c, d, rho, e);
  if (!shareVertices) {
    addQuad(mesh, a, d, c, b, rho, e);
    return;
  }
  const int64_t face = mesh.sourceFace.back() + 1;
  // (a, d, c) and (a, c, b): the front's triangles (a, c, d) and (a, b, c) turned over.
  for (Triangle t :
       {Triangle{front, front + 3, front + 2}, Triangle{front, front + 2, front + 1}}) {
    mesh.triangles.push_back(t);
    mesh.sourceFace.push_back(face);
    mesh.reflectance.push_back(rho);
    mesh.emission.push_back(e);
  }
}

/// Source faces of platesWithBlocker().
enum BlockerFace : int64_t { kBottomPlate = 0, kTopPlate = 1, kBlockerDown = 2, kBlockerUp = 3 };

/// Two unit squares at distance 1 (the bottom one at z = 0 facing up and emitting, the top one
/// at z = 1 facing down) with the square [0.25, 0.75]² at z = 0.5 between them: a face towards
/// the bottom plate (`down`), one towards the top plate (`up`), or both back to back
/// (addTwoSidedQuad). Source faces as in BlockerFace (kBlockerUp is 2 when there is no down
/// face).
inline Mesh platesWithBlocker(bool down, bool up, bool shareVertices = false) {
  Mesh mesh = parallelPlates(1, 1, 1);
  const Rgb rho{0.5, 0.5, 0.5}, none{0, 0, 0};
  const Vec3 a{0.25, 0.25, 0.5}, b{0.75, 0.25, 0.5}, c{0.75, 0.75, 0.5}, d{0.25, 0.75, 0.5};
  if (down && up) {
    addTwoSidedQuad(mesh, a, d, c, b, rho, none, shareVertices);
  } else if (down) {
    addQuad(mesh, a, d, c, b, rho, none);
  } else if (up) {
    addQuad(mesh, a, b, c, d, rho, none);
  }
  return mesh;
}

}  // namespace radiosity::testing
