// The patches shared among surfaces (partition::refine's surfaceShare): a 1 m room on a ground
// of 10^6 m² gets patches on each of its surfaces, the room's floor apart from the ground around
// it (the walls stand on the line between them); a scene of very many surfaces is left to the
// area bound.
#include <gtest/gtest.h>

#include <map>

#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::partition {
namespace {

const Rgb kGrey{0.5, 0.5, 0.5}, kNone{0, 0, 0};

// A closed 1 × 0.75 × 1 room (faces inward: floor, ceiling, four walls, faces 0–5) standing on
// a 1,000 × 1,000 ground (face 6, facing up, running under the room).
Mesh roomOnGround() {
  Mesh mesh;
  const double h = 0.75;
  testing::addQuad(mesh, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, kGrey, kNone);
  testing::addQuad(mesh, {0, h, 0}, {1, h, 0}, {1, h, 1}, {0, h, 1}, kGrey, kNone);
  testing::addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, h, 0}, {0, h, 0}, kGrey, kNone);
  testing::addQuad(mesh, {0, 0, 1}, {0, h, 1}, {1, h, 1}, {1, 0, 1}, kGrey, kNone);
  testing::addQuad(mesh, {0, 0, 0}, {0, h, 0}, {0, h, 1}, {0, 0, 1}, kGrey, kNone);
  testing::addQuad(mesh, {1, 0, 0}, {1, 0, 1}, {1, h, 1}, {1, h, 0}, kGrey, kNone);
  testing::addQuad(mesh, {-500, 0, -500}, {-500, 0, 500}, {500, 0, 500}, {500, 0, -500}, kGrey,
                   kNone);
  return mesh;
}

std::map<int64_t, int64_t> patchesPerFace(const Mesh& mesh) {
  std::map<int64_t, int64_t> count;
  for (int64_t face : mesh.sourceFace) ++count[face];
  return count;
}

TEST(SurfaceShare, EachSurfaceOfARoomOnALargeGroundGetsItsPart) {
  const Mesh scene = cutAtContacts(roomOnGround());  // the floor covers the ground under it
  const ContactEdges edges = contactEdges(scene);
  const double bound = scene.totalArea() / 4000;
  // The bound alone: the room's faces stay 2 triangles each (or a few, along contact lines).
  const auto plain = patchesPerFace(refine(scene, bound, nullptr, &edges));
  for (int64_t face = 0; face < 6; ++face) EXPECT_LE(plain.at(face), 8) << face;
  // 1,000 shared among 7 surfaces (the room's six, the ground): 142 each at least, the floor
  // apart from the ground around it.
  const auto shared = patchesPerFace(refine(scene, bound, nullptr, &edges, 1000));
  for (int64_t face = 0; face < 6; ++face) EXPECT_GE(shared.at(face), 1000 / 7) << face;
  // The ground's part is below what the bound gives it: it gains only the conforming closures
  // of the splits around the room.
  EXPECT_LT(shared.at(6), plain.at(6) + plain.at(6) / 20);
}

TEST(SurfaceShare, VeryManySurfacesAreLeftToTheAreaBound) {
  // 200 separate small plates: 1,000 / 200 = 5 patches each, fewer than a part is worth.
  Mesh scene;
  for (int k = 0; k < 200; ++k)
    testing::addQuad(scene, {2.0 * k, 0, 0}, {2.0 * k, 0, 1}, {2.0 * k + 1, 0, 1},
                     {2.0 * k + 1, 0, 0}, kGrey, kNone);
  const double bound = scene.totalArea() / 100;
  EXPECT_EQ(refine(scene, bound, nullptr, nullptr, 1000).triangles, refine(scene, bound).triangles);
  // 100 plates: 10 each, and each gets them.
  Mesh fewer;
  for (int k = 0; k < 100; ++k)
    testing::addQuad(fewer, {2.0 * k, 0, 0}, {2.0 * k, 0, 1}, {2.0 * k + 1, 0, 1},
                     {2.0 * k + 1, 0, 0}, kGrey, kNone);
  for (const auto& [face, count] : patchesPerFace(refine(fewer, 1, nullptr, nullptr, 1000)))
    EXPECT_GE(count, 10) << face;
}

}  // namespace
}  // namespace radiosity::partition
