// View3D's input files (.vs3): the manual's cube as published, combined surfaces, obstructions,
// comments and the end-of-data line; and every line View3D's users could get wrong refused with
// file:line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "scene_fixture.h"
#include "view3d_files.h"

namespace radiosity {
namespace {

using testing::expectInputError;
using testing::hasWarningWith;
using testing::SceneTest;

const std::string kHead = "T t\nF 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\n";

TEST_F(SceneTest, Vs3CubeAsPublished) {
  const Mesh mesh = loadScene(write("cube.vs3", testing::kView3dCube));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  ASSERT_EQ(mesh.triangleCount(), 12);
  ASSERT_EQ(mesh.labelNames.size(), 6u);
  EXPECT_EQ(mesh.labelNames[0], "zeq0");
  EXPECT_EQ(mesh.labelNames[5], "yeq1");
  for (int64_t t = 0; t < 12; ++t) {
    EXPECT_EQ(mesh.sourceFace[t], t / 2);  // surface k is source face k - 1
    EXPECT_EQ(mesh.label[t], t / 2);
    EXPECT_EQ(mesh.reflectance[t], (Rgb{0.5, 0.5, 0.5}));  // 1 - emissivity
    EXPECT_EQ(mesh.emission[t], (Rgb{0, 0, 0}));
    // Every face looks into the cube.
    const Vec3 inward = Vec3{0.5, 0.5, 0.5} - mesh.centroid(t);
    EXPECT_GT(dot(mesh.normal(t), inward), 0) << t;
  }
  EXPECT_NEAR(mesh.totalArea(), 6, 1e-12);
  EXPECT_EQ(mesh.labelEmissivity, std::vector<double>(6, 0.5));  // for --thermal
}

TEST_F(SceneTest, Vs3CombinedSurfacesShareALabelAndObstructionsAreTwoSided) {
  const Mesh mesh =
      loadScene(write("c.vs3",
                      "T combined\nC encl=0 eps=1.e-4, maxU=8\nF 3\n"
                      "V 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nV 5 2 0 0\nV 6 2 1 0\n"
                      "V 7 0 0 1\nV 8 1 0 1\nV 9 1 1 1\n"
                      "/ a comment line\n"
                      "s 1 1 2 3 4 0 0 0.9 floor ! the first half\n"
                      "S 2 2 5 6 3 0 1 0.8 floor-b\n"
                      "S 3 7 9 8 0 0 0 0.5 tri\n"
                      "O 4 1 2 9 0\n"
                      "End of data\n"
                      "S 5 this is not read\n"));
  ASSERT_EQ(mesh.labelNames.size(), 3u);
  EXPECT_EQ(mesh.labelNames[0], "floor");
  EXPECT_EQ(mesh.labelNames[1], "tri");
  EXPECT_EQ(mesh.labelNames[2], "obstruction 4");
  ASSERT_EQ(mesh.triangleCount(), 2 + 2 + 1 + 2);
  EXPECT_EQ(mesh.label[2], 0);  // surface 2 combined with surface 1
  EXPECT_EQ(mesh.sourceFace[2], 1);
  EXPECT_NEAR(mesh.reflectance[2][0], 0.2, 1e-15);
  EXPECT_EQ(mesh.sourceFace[4], 2);
  // The obstruction: black, once each way.
  EXPECT_EQ(mesh.sourceFace[5], 3);
  EXPECT_EQ(mesh.sourceFace[6], 3);
  EXPECT_EQ(mesh.reflectance[5], (Rgb{0, 0, 0}));
  EXPECT_NEAR(dot(mesh.normal(5), mesh.normal(6)), -1, 1e-12);
  // Parts of one surface with other emissivities (0.9, 0.8) leave it none; obstructions have none.
  ASSERT_EQ(mesh.labelEmissivity.size(), 3u);
  EXPECT_TRUE(std::isnan(mesh.labelEmissivity[0]));
  EXPECT_EQ(mesh.labelEmissivity[1], 0.5);
  EXPECT_TRUE(std::isnan(mesh.labelEmissivity[2]));
}

// A window in the middle of a 4 × 3 wall and a door on its bottom edge (View3D's subsurfaces):
// cut out of the wall, each a surface of its own with its own label and source face.
TEST_F(SceneTest, Vs3SubsurfacesAreCutOutOfTheirBase) {
  const Mesh mesh = loadScene(write("s.vs3",
                                    "T wall\nF 3\nV 1 0 0 0\nV 2 4 0 0\nV 3 4 3 0\nV 4 0 3 0\n"
                                    "V 5 1 1 0\nV 6 2 1 0\nV 7 2 2 0\nV 8 1 2 0\n"
                                    "V 9 2.5 0 0\nV 10 3.5 0 0\nV 11 3.5 2 0\nV 12 2.5 2 0\n"
                                    "S 1 1 2 3 4 0 0 0.9 wall\n"
                                    "S 2 5 6 7 8 1 0 0.8 window\n"
                                    "S 3 9 10 11 12 1 0 0.7 door\n"));
  ASSERT_EQ(mesh.labelNames, (std::vector<std::string>{"wall", "window", "door"}));
  double area[3] = {0, 0, 0};
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const int64_t face = mesh.sourceFace[t];
    ASSERT_GE(face, 0);
    ASSERT_LT(face, 3);
    EXPECT_EQ(mesh.label[t], face);
    EXPECT_NEAR(mesh.reflectance[t][0], 0.1 * static_cast<double>(face + 1), 1e-15);
    EXPECT_GT(mesh.normal(t).z, 0) << t;  // every part faces the wall's way
    area[face] += mesh.area(t);
    const Vec3 c = mesh.centroid(t);
    if (face == 0) {  // no part of the wall under the window or the door
      EXPECT_FALSE(c.x > 1 && c.x < 2 && c.y > 1 && c.y < 2) << t;
      EXPECT_FALSE(c.x > 2.5 && c.x < 3.5 && c.y < 2) << t;
    }
  }
  EXPECT_NEAR(area[0], 12 - 1 - 2, 1e-12);
  EXPECT_NEAR(area[1], 1, 1e-12);
  EXPECT_NEAR(area[2], 2, 1e-12);
}

TEST_F(SceneTest, Vs3WarnsOfWhatItDoesNotCompute) {
  const Mesh mesh = loadScene(write("w.vs3",
                                    "T w\nC emit=1 row=2\nF 3\nV 1 0 0 0\nV 2 1 0 0\n"
                                    "V 3 1 1 0\nX 1 2 3\nS 1 1 2 3 0 0 0 0.5 a\n"
                                    "S 2 1 3 2 0 0 0 0.5 a\n"));
  EXPECT_TRUE(hasWarningWith(mesh, "emit=1"));
  EXPECT_TRUE(hasWarningWith(mesh, "row=2 is ignored"));
  EXPECT_TRUE(hasWarningWith(mesh, "coordinate-transformation"));
  EXPECT_TRUE(hasWarningWith(mesh, "both named 'a'"));
}

TEST_F(SceneTest, Vs3MistakesAreRefusedWithFileAndLine) {
  struct Case {
    std::string text;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {"T t\nF 3a\n", {"b.vs3:2:", "3a", "F 3"}},
      {"T t\nF 2\n", {"b.vs3:2:", "F 3"}},
      {"T t\nV 1 0 0 0\n", {"b.vs3:2:", "after the geometry line"}},
      {"T t\nC epsilon=1\nF 3\n", {"b.vs3:2:", "unknown control word 'epsilon'"}},
      {"T t\nC eps=x\nF 3\n", {"b.vs3:2:", "needs a number"}},
      {"T t\nF 3\nV 2 0 0 0\n", {"b.vs3:3:", "vertex 2 out of sequence"}},
      {"T t\nF 3\nV 1 0 nan 0\n", {"b.vs3:3:", "not finite"}},
      {"T t\nF 3\nV 1 0 1e31 0\n", {"b.vs3:3:", "exceeds 1e30"}},
      {"T t\nF 3\nV 1 0 0\n", {"b.vs3:3:", "V n x y z"}},
      {kHead + "S 2 1 2 3 4 0 0 0.5 a\n", {"b.vs3:7:", "surface 2 out of sequence"}},
      {kHead + "S 1 1 2 3 5 0 0 0.5 a\n", {"b.vs3:7:", "vertex 5 does not exist"}},
      {kHead + "S 1 1 2 3 4 0 0 0.5 my wall\n", {"b.vs3:7:", "no blanks"}},
      {kHead + "S 1 1 2 3 4 0 0 0 a\n", {"b.vs3:7:", "emissivity 0 is not in (0, 1]"}},
      {kHead + "S 1 1 2 3 4 0 0 1.5 a\n", {"b.vs3:7:", "emissivity 1.5"}},
      {kHead + "S 1 1 2 3 4 0 0 0.5 a\nS 2 1 2 3 0 0 3 0.5 b\n", {"b.vs3:8:", "cmb 3"}},
      {kHead + "S 1 1 2 3 4 0 1 0.5 a\n", {"b.vs3:7:", "cmb 1"}},
      {kHead + "S 1 1 2 3 4 0 0 0.5 a\nM 2 1 2 3 0 1 0 0.5 b\n", {"b.vs3:8:", "masking"}},
      {kHead + "O 1 1 2 3 0\nS 2 1 2 3 4 0 0 0.5 a\n", {"b.vs3:8:", "after an obstruction"}},
      {kHead + "S 1 1 3 2 4 0 0 0.5 a\n", {"b.vs3:7:", "crosses itself"}},
      {kHead + "Q 1 2\n", {"b.vs3:7:", "unknown line 'Q'"}},
      {kHead, {"b.vs3", "no surfaces"}},
      {std::string("T t\nF 3\x01\n"), {"b.vs3:2:", "control byte"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    expectInputError([&] { loadScene(write("b.vs3", c.text)); }, c.mentions);
  }
}

// Subsurfaces View3D could not take out of their base: each refused with its own line (the
// unit square's wall is surface 1, on line 21).
TEST_F(SceneTest, Vs3SubsurfacesOutsideTheirBaseAreRefused) {
  const std::string wall = kHead +
                           "V 5 .25 .25 0\nV 6 .75 .25 0\nV 7 .75 .75 0\nV 8 .25 .75 0\n"
                           "V 9 .5 .5 0\nV 10 .9 .5 0\nV 11 .9 .9 0\nV 12 .5 .9 0\n"
                           "V 13 .25 .25 .1\nV 14 1.5 .5 0\n"
                           "V 15 .4 .4 0\nV 16 .6 .4 0\nV 17 .6 .6 0\nV 18 .4 .6 0\n"
                           "S 1 1 2 3 4 0 0 0.5 wall\n";
  struct Case {
    std::string text;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {kHead + "S 1 1 2 3 4 2 0 0.5 a\nS 2 1 2 3 4 0 0 0.5 b\n",
       {"b.vs3:7:", "surface 1 (a subsurface of surface 2)", "earlier radiating surface"}},
      {wall + "S 2 5 6 7 8 9 0 0.5 w\n", {"b.vs3:22:", "earlier radiating surface"}},
      {wall + "S 2 5 6 7 8 1 0 0.5 w\nS 3 15 16 17 18 2 0 0.5 v\n",
       {"b.vs3:23:", "not itself a subsurface"}},
      {wall + "S 2 13 6 7 8 1 0 0.5 w\n", {"b.vs3:22:", "off its base's plane"}},
      {wall + "S 2 5 8 7 6 1 0 0.5 w\n", {"b.vs3:22:", "faces the other way"}},
      {wall + "S 2 5 14 7 8 1 0 0.5 w\n", {"b.vs3:22:", "vertex 14 lies outside its base"}},
      {wall + "S 2 5 6 7 8 1 0 0.5 w\nS 3 9 10 11 12 1 0 0.5 v\n",
       {"b.vs3:23:", "surface 3", "overlaps another subsurface"}},
      {wall + "S 2 5 6 7 8 1 0 0.5 w\nS 3 15 16 17 18 1 0 0.5 v\n",
       {"b.vs3:23:", "surface 3", "overlaps another subsurface"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    expectInputError([&] { loadScene(write("b.vs3", c.text)); }, c.mentions);
  }
}

}  // namespace
}  // namespace radiosity
