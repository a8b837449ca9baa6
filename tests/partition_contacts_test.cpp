// Cutting triangles along contacts (partition::cutAtContacts): objects resting on a floor that
// runs under them, a wall through a floor, coincident faces triangulated differently.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "io/scene/scene.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::partition {
namespace {

const Rgb kGrey{0.5, 0.5, 0.5}, kNone{0, 0, 0};

// A box of 4 walls and a top (no bottom, as the Cornell blocks are written) standing on the
// plane y = 0 over [x0, x1] × [z0, z1], faces outwards.
void addBlock(Mesh& mesh, double x0, double x1, double z0, double z1, double height) {
  const Vec3 a{x0, 0, z0}, b{x1, 0, z0}, c{x1, 0, z1}, d{x0, 0, z1};
  const Vec3 up{0, height, 0};
  testing::addQuad(mesh, a + up, d + up, c + up, b + up, kGrey, kNone);  // top, facing +y
  testing::addQuad(mesh, a, b, b + up, a + up, kGrey, kNone);            // z = z0, facing -z
  testing::addQuad(mesh, b, c, c + up, b + up, kGrey, kNone);            // x = x1, facing +x
  testing::addQuad(mesh, c, d, d + up, c + up, kGrey, kNone);            // z = z1, facing +z
  testing::addQuad(mesh, d, a, a + up, d + up, kGrey, kNone);            // x = x0, facing -x
}

// A 1 × 1 floor at y = 0 facing up, one quad (two triangles) running under whatever stands on it.
Mesh floorQuad() {
  Mesh mesh;
  testing::addQuad(mesh, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, kGrey, kNone);
  return mesh;
}

// Where point p lies against the axis-aligned footprint: -1 inside, 0 on its boundary, 1 outside.
int against(Vec3 p, double x0, double x1, double z0, double z1) {
  if (p.x > x0 && p.x < x1 && p.z > z0 && p.z < z1) return -1;
  if (p.x < x0 || p.x > x1 || p.z < z0 || p.z > z1) return 1;
  return 0;
}

TEST(ContactCuts, FloorUnderABlockIsCutAlongItsWalls) {
  Mesh scene = floorQuad();
  addBlock(scene, 0.3, 0.6, 0.2, 0.7, 0.4);
  ContactReport report;
  const Mesh cut = cutAtContacts(scene, &report);
  // The floor's two triangles; the walls meet the floor along their own edges, which separates
  // nothing on them (cutting them there would only fan them into needles).
  EXPECT_EQ(report.trianglesCut, 2);
  int64_t floorPieces = 0;
  for (int64_t t = 0; t < cut.triangleCount(); ++t) floorPieces += cut.sourceFace[t] == 0;
  EXPECT_GT(floorPieces, 2);
  EXPECT_NEAR(cut.totalArea(), scene.totalArea(), 1e-12);
  double under = 0;
  for (int64_t t = 0; t < cut.triangleCount(); ++t) {
    if (cut.sourceFace[t] != 0) continue;  // the floor
    EXPECT_GT(cut.normal(t).y, 0.99) << "a piece turned over";
    // No piece straddles the footprint's boundary: its corners are all on one side.
    int inside = 0, outside = 0;
    for (int k = 0; k < 3; ++k) {
      const int side = against(cut.corner(t, k), 0.3, 0.6, 0.2, 0.7);
      inside += side<0, outside += side> 0;
    }
    EXPECT_FALSE(inside > 0 && outside > 0) << "floor piece " << t << " straddles the block";
    if (against(cut.centroid(t), 0.3, 0.6, 0.2, 0.7) < 0) under += cut.area(t);
  }
  EXPECT_NEAR(under, 0.3 * 0.5, 1e-12);
}

TEST(ContactCuts, NeighboursSharingEdgesAreLeftAsTheyAre) {
  // A closed box: every triangle touches its neighbours along shared edges and corners only.
  const Mesh box = testing::closedBox(0.5, 1.0);
  ContactReport report;
  const Mesh cut = cutAtContacts(box, &report);
  EXPECT_EQ(report.trianglesCut, 0);
  EXPECT_EQ(cut.triangles, box.triangles);
  EXPECT_EQ(cut.vertices, box.vertices);
  // The same when the faces do not share vertex indices, only positions.
  Mesh loose;
  for (int64_t t = 0; t < box.triangleCount(); ++t) {
    const auto base = static_cast<int64_t>(loose.vertices.size());
    for (int k = 0; k < 3; ++k) loose.vertices.push_back(box.corner(t, k));
    loose.triangles.push_back({base, base + 1, base + 2});
    loose.sourceFace.push_back(t);
    loose.reflectance.push_back(kGrey);
    loose.emission.push_back(kNone);
  }
  EXPECT_EQ(cutAtContacts(loose).triangleCount(), loose.triangleCount());
}

TEST(ContactCuts, AWallThroughAFloorCutsBoth) {
  Mesh scene = floorQuad();
  // A wall in the plane x = 0.4 from y = -0.5 to 0.5, across the whole floor (z from 0 to 1).
  testing::addQuad(scene, {0.4, -0.5, 0}, {0.4, -0.5, 1}, {0.4, 0.5, 1}, {0.4, 0.5, 0}, kGrey,
                   kNone);
  const Mesh cut = cutAtContacts(scene);
  for (int64_t t = 0; t < cut.triangleCount(); ++t) {
    int below = 0, above = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = cut.corner(t, k);
      const double side = cut.sourceFace[t] == 0 ? p.x - 0.4 : p.y;  // floor: x; wall: y
      below += side<0, above += side> 0;
    }
    EXPECT_FALSE(below > 0 && above > 0) << "piece " << t << " of face " << cut.sourceFace[t];
  }
  EXPECT_NEAR(cut.totalArea(), scene.totalArea(), 1e-12);
}

// Triangles of a mesh as sets of corner positions, to compare triangulations.
std::multiset<std::array<std::array<double, 3>, 3>> cornerSets(const Mesh& mesh, int64_t face) {
  std::multiset<std::array<std::array<double, 3>, 3>> sets;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] != face) continue;
    std::array<std::array<double, 3>, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = mesh.corner(t, k);
      corners[k] = {p.x, p.y, p.z};
    }
    std::sort(corners.begin(), corners.end());
    sets.insert(corners);
  }
  return sets;
}

TEST(ContactCuts, CoincidentFacesComeOutTriangulatedAlike) {
  // A square written twice back to back, each side along its own diagonal (as two modelling
  // tools would), and once more subdivided differently (four triangles around its centre).
  Mesh scene;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
  testing::addQuad(scene, a, b, c, d, kGrey, kNone);  // diagonal a–c, facing +z
  testing::addQuad(scene, b, a, d, c, kGrey, kNone);  // diagonal b–d, facing −z
  const Mesh cut = cutAtContacts(scene);
  EXPECT_EQ(cornerSets(cut, 0), cornerSets(cut, 1));
  EXPECT_EQ(cornerSets(cut, 0).size(), 4u);  // both cut along both diagonals
  for (int64_t t = 0; t < cut.triangleCount(); ++t)
    EXPECT_NEAR(std::abs(cut.normal(t).z), 1, 1e-12);
  for (int64_t t = 0; t < cut.triangleCount(); ++t)
    EXPECT_EQ(cut.normal(t).z > 0, cut.sourceFace[t] == 0) << "a piece turned over";
}

TEST(ContactCuts, TheSameAtAnyScale) {
  Mesh scene = floorQuad();
  addBlock(scene, 0.3, 0.6, 0.2, 0.7, 0.4);
  const Mesh unit = cutAtContacts(scene);
  for (double scale : {1e-30, 1e30}) {
    Mesh scaled = scene;
    for (Vec3& v : scaled.vertices) v = scale * v;
    const Mesh cut = cutAtContacts(scaled);
    ASSERT_EQ(cut.triangles, unit.triangles) << scale;
    for (size_t v = 0; v < cut.vertices.size(); ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(cut.vertices[v][k] / scale, unit.vertices[v][k], 1e-14) << scale;
  }
}

TEST(ContactCuts, ThePublishedCornellFloorIsCutAroundBothBlocks) {
  const Mesh published = loadScene("builtin:cornell?cut_floor=0");
  const Mesh handCut = loadScene("builtin:cornell");
  ContactReport report;
  const Mesh cut = cutAtContacts(published, &report);
  EXPECT_GT(report.trianglesCut, 0);
  EXPECT_NEAR(cut.totalArea(), published.totalArea(), 1e-9 * published.totalArea());
  // The floor under the blocks is pieces of its own: the floor's area outside the footprints
  // is the hand-cut floor's.
  auto floorArea = [](const Mesh& mesh, bool outsideOnly) {
    const std::vector<std::vector<std::array<double, 2>>> footprints = {
        {{130, 65}, {290, 114}, {240, 272}, {82, 225}},
        {{423, 247}, {472, 406}, {314, 456}, {265, 296}}};
    auto inside = [&](Vec3 p) {
      for (const auto& f : footprints) {
        bool in = true;
        for (size_t k = 0; k < f.size(); ++k) {
          const auto& u = f[k];
          const auto& w = f[(k + 1) % f.size()];
          in = in && (w[0] - u[0]) * (p.z - u[1]) - (w[1] - u[1]) * (p.x - u[0]) > 0;
        }
        if (in) return true;
      }
      return false;
    };
    double area = 0;
    for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
      if (mesh.normal(t).y < 0.99 || mesh.corner(t, 0).y != 0) continue;
      if (outsideOnly && inside(mesh.centroid(t))) continue;
      area += mesh.area(t);
    }
    return area;
  };
  EXPECT_NEAR(floorArea(cut, true), floorArea(handCut, false), 1e-6 * floorArea(handCut, false));
}

TEST(ContactCuts, NearlyCoincidentLinesLeaveNoSlivers) {
  // builtin:cornell's floor is cut by hand to the blocks' footprints in double, so its edges run
  // within 1e-13 of the slanted walls' feet: cutting along both would leave slivers that rounding
  // flattens (zero-area patches, NaN rays). Snapped, every piece stays a sound triangle.
  const Mesh cut = cutAtContacts(loadScene("builtin:cornell"));
  for (int64_t t = 0; t < cut.triangleCount(); ++t) {
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = cut.corner(t, (k + 1) % 3) - cut.corner(t, k);
      longest = std::max(longest, dot(d, d));
    }
    EXPECT_LT(longest / cut.area(t), 1e3) << "piece " << t << " of face " << cut.sourceFace[t];
  }
}

}  // namespace
}  // namespace radiosity::partition
