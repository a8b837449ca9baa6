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
      {kHead + "S 1 1 2 3 4 0 0 0.5 a\nS 2 1 2 3 0 1 0 0.5 b\n", {"b.vs3:8:", "subsurface"}},
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

}  // namespace
}  // namespace radiosity
