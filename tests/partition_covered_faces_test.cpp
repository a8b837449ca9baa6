// Faces laid over others (partition::cutAtContacts): a poster on a wall, a panel flush on a
// ceiling, a room's floor on the ground, one face given twice. The face laid over covers the
// one below, whose covered part is left out; faces back to back (an object resting on a floor)
// are not laid over each other.
#include <gtest/gtest.h>

#include <cmath>

#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::partition {
namespace {

const Rgb kGrey{0.5, 0.5, 0.5}, kNone{0, 0, 0};

// The area of each input face in `mesh`.
double faceArea(const Mesh& mesh, int64_t face) {
  double area = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    if (mesh.sourceFace[t] == face) area += mesh.area(t);
  return area;
}

// A 4 × 3 wall in the plane z = 0 facing +z, and a 2 × 1.5 poster on it, facing the same way.
Mesh wallWithPoster() {
  Mesh mesh;
  testing::addQuad(mesh, {0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, kGrey, kNone);
  testing::addQuad(mesh, {1, 1, 0}, {3, 1, 0}, {3, 2.5, 0}, {1, 2.5, 0}, kGrey, kNone);
  return mesh;
}

TEST(CoveredFaces, APosterOnAWallCoversTheWallUnderIt) {
  const Mesh scene = wallWithPoster();
  ContactReport report;
  const Mesh cut = cutAtContacts(scene, &report);
  EXPECT_NEAR(faceArea(cut, 1), 3, 1e-12);       // the poster, whole
  EXPECT_NEAR(faceArea(cut, 0), 12 - 3, 1e-12);  // the wall around it
  // Nothing of the wall is left under the poster.
  for (int64_t t = 0; t < cut.triangleCount(); ++t) {
    if (cut.sourceFace[t] != 0) continue;
    const Vec3 c = cut.centroid(t);
    EXPECT_FALSE(c.x > 1 && c.x < 3 && c.y > 1 && c.y < 2.5) << "wall piece " << t;
    EXPECT_GT(cut.normal(t).z, 0.99) << "a piece turned over";
  }
  ASSERT_EQ(report.covered.size(), 1u);
  EXPECT_EQ(report.covered[0].face, 0);
  EXPECT_EQ(report.covered[0].by, 1);
  EXPECT_NEAR(report.covered[0].area, 3, 1e-12);
  EXPECT_NEAR(report.coveredArea, 3, 1e-12);
}

TEST(CoveredFaces, WhicheverComesFirstInTheFile) {
  // The poster first: the smaller face still lies over the larger.
  Mesh scene;
  testing::addQuad(scene, {1, 1, 0}, {3, 1, 0}, {3, 2.5, 0}, {1, 2.5, 0}, kGrey, kNone);
  testing::addQuad(scene, {0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, kGrey, kNone);
  const Mesh cut = cutAtContacts(scene);
  EXPECT_NEAR(faceArea(cut, 0), 3, 1e-12);
  EXPECT_NEAR(faceArea(cut, 1), 9, 1e-12);
}

TEST(CoveredFaces, AFinelyMeshedWallIsOneRegion) {
  // The wall as an exporter writes it: 12 quads of 1 × 1 (each smaller than the poster). The
  // wall is the larger flat region, so the poster still lies over it.
  Mesh scene;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      testing::addQuad(scene, {double(i), double(j), 0}, {i + 1.0, double(j), 0},
                       {i + 1.0, j + 1.0, 0}, {double(i), j + 1.0, 0}, kGrey, kNone);
  testing::addQuad(scene, {0.5, 0.5, 0}, {2.5, 0.5, 0}, {2.5, 2, 0}, {0.5, 2, 0}, kGrey, kNone);
  ContactReport report;
  const Mesh cut = cutAtContacts(scene, &report);
  EXPECT_NEAR(faceArea(cut, 12), 3, 1e-12);
  EXPECT_NEAR(cut.totalArea(), 12, 1e-12);
  EXPECT_NEAR(report.coveredArea, 3, 1e-12);
}

TEST(CoveredFaces, ARoomsFloorCoversTheGroundItStandsOn) {
  // A 100 × 100 ground facing up, and a 4 × 4 floor on it (facing up too, into the room).
  Mesh scene;
  testing::addQuad(scene, {-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, kGrey, kNone);
  testing::addQuad(scene, {0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}, kGrey, kNone);
  const Mesh cut = cutAtContacts(scene);
  EXPECT_NEAR(faceArea(cut, 1), 16, 1e-9);
  EXPECT_NEAR(faceArea(cut, 0), 10000 - 16, 1e-9);
}

TEST(CoveredFaces, AFaceGivenTwiceIsKeptOnce) {
  Mesh scene;
  testing::addQuad(scene, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, kGrey, kNone);
  testing::addQuad(scene, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, kGrey, kNone);
  ContactReport report;
  const Mesh cut = cutAtContacts(scene, &report);
  EXPECT_NEAR(cut.totalArea(), 1, 1e-12);
  EXPECT_NEAR(faceArea(cut, 1), 1, 1e-12);  // the later one, drawn last
  EXPECT_NEAR(report.coveredArea, 1, 1e-12);
  // Triangulated differently (along the other diagonal), the same.
  Mesh other;
  testing::addQuad(other, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, kGrey, kNone);
  testing::addQuad(other, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, kGrey, kNone);
  EXPECT_NEAR(cutAtContacts(other).totalArea(), 1, 1e-12);
}

TEST(CoveredFaces, FacesBackToBackAreBothKept) {
  // A plate lying on a floor, its underside facing down onto it (an object resting on a floor),
  // and a square written twice back to back (a thin two-sided surface): nothing lies over
  // anything; the floor under the plate is cut, and left for the hidden-patch probe.
  Mesh scene;
  testing::addQuad(scene, {0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}, kGrey, kNone);  // up
  testing::addQuad(scene, {1, 0, 1}, {2, 0, 1}, {2, 0, 2}, {1, 0, 2}, kGrey, kNone);  // down
  testing::addQuad(scene, {0, 5, 0}, {1, 5, 0}, {1, 5, 1}, {0, 5, 1}, kGrey, kNone);
  testing::addQuad(scene, {0, 5, 0}, {0, 5, 1}, {1, 5, 1}, {1, 5, 0}, kGrey, kNone);
  ContactReport report;
  const Mesh cut = cutAtContacts(scene, &report);
  EXPECT_NEAR(cut.totalArea(), scene.totalArea(), 1e-12);
  EXPECT_TRUE(report.covered.empty());
  EXPECT_GT(report.trianglesCut, 0);
}

}  // namespace
}  // namespace radiosity::partition
