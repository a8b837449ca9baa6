// PLY and OFF files through OpenMesh: colours, emission and the default material, and broken or
// malformed files refused as input errors (headers before OpenMesh ever sees them).
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

using namespace std::string_literals;  // "...\0..."s keeps the NUL bytes
using testing::expectInputError;
using testing::expectNear;
using testing::hasWarningWith;
using testing::SceneTest;

TEST_F(SceneTest, PlyWithFaceColours) {
  const std::string path = write("c.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 5\n"
                                 "property double x\nproperty double y\nproperty double z\n"
                                 "element face 2\nproperty list uchar int vertex_indices\n"
                                 "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                 "end_header\n"
                                 "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"
                                 "4 0 1 2 3 255 0 51\n"
                                 "3 0 1 4 0 102 255\n");
  const Mesh mesh = loadScene(path);
  ASSERT_EQ(mesh.triangleCount(), 3);
  EXPECT_EQ(mesh.sourceFace, (std::vector<int64_t>{0, 0, 1}));
  EXPECT_NEAR(mesh.area(0) + mesh.area(1), 1, 1e-12);
  expectNear(mesh.normal(0), {0, 0, 1});
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mesh.reflectance[0][c], (Rgb{1, 0, 0.2})[c], 1e-6);
    EXPECT_NEAR(mesh.reflectance[2][c], (Rgb{0, 0.4, 1})[c], 1e-6);
    EXPECT_EQ(mesh.emission[2][c], 0);
  }
  EXPECT_EQ(mesh.vertices[4], (Vec3{0.5, 0.5, 1}));
  EXPECT_FALSE(hasWarningWith(mesh, "no face colours"));
}

TEST_F(SceneTest, PlyWithoutColoursGetsTheDefaultMaterial) {
  const std::string path = write("n.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 3\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "element face 1\nproperty list uchar int vertex_indices\n"
                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const Mesh mesh = loadScene(path);
  ASSERT_EQ(mesh.triangleCount(), 1);
  EXPECT_EQ(mesh.reflectance[0], detail::kDefaultReflectance);
  EXPECT_TRUE(hasWarningWith(mesh, "n.ply: no face colours"));
}

TEST_F(SceneTest, PlyEmissionFromEmitFaceProperties) {
  const std::string header =
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  const std::string vertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  // float and double are exitances as given.
  const Mesh real = loadScene(write("e.ply", "ply\nformat ascii 1.0\n" + header +
                                                 "property float emit_red\nproperty double "
                                                 "emit_green\nproperty float emit_blue\n"
                                                 "end_header\n" +
                                                 vertices +
                                                 "3 0 1 2 255 255 255 1.5 2.25 40\n"
                                                 "3 0 2 3 51 102 153 0 0 0\n"));
  ASSERT_EQ(real.triangleCount(), 2);
  EXPECT_EQ(real.emission[0], (Rgb{1.5, 2.25, 40}));
  EXPECT_EQ(real.emission[1], (Rgb{0, 0, 0}));
  EXPECT_NEAR(real.reflectance[1][1], 0.4, 1e-6);
  EXPECT_EQ(real.labelNames, (std::vector<std::string>{"e.ply"}));
  EXPECT_EQ(real.label, (std::vector<int32_t>{0, 0}));
  // uchar is divided by 255 like a colour, in ASCII (which OpenMesh 9 cannot read as uchar
  // custom properties on its own) and in binary.
  const std::string bytes =
      "property uchar emit_red\nproperty uchar emit_green\n"
      "property uchar emit_blue\nend_header\n";
  const Mesh ascii =
      loadScene(write("a.ply", "ply\nformat ascii 1.0\n" + header + bytes + vertices +
                                   "3 0 1 2 255 255 255 255 51 0\n"
                                   "3 0 2 3 51 102 153 0 0 102\n"));
  ASSERT_EQ(ascii.triangleCount(), 2);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(ascii.emission[0][c], (Rgb{1, 0.2, 0})[c], 1e-12);
    EXPECT_NEAR(ascii.emission[1][c], (Rgb{0, 0, 0.4})[c], 1e-12);
    EXPECT_NEAR(ascii.reflectance[1][c], (Rgb{0.2, 0.4, 0.6})[c], 1e-6);
  }
  std::string binary = "ply\nformat binary_little_endian 1.0\n" + header + bytes;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) {
    binary.append(reinterpret_cast<const char*>(&v), 4);  // the test hosts are little-endian
  }
  for (const auto& [a, b, c] : {std::array<int32_t, 3>{0, 1, 2}, std::array<int32_t, 3>{0, 2, 3}}) {
    binary += '\3';
    for (int32_t i : {a, b, c}) binary.append(reinterpret_cast<const char*>(&i), 4);
    binary += a + b + c == 3 ? "\xff\xff\xff\xff\x33\x00"s : "\x33\x66\x99\x00\x00\x66"s;
  }
  const Mesh packed = loadScene(write("b.ply", binary));
  ASSERT_EQ(packed.triangleCount(), 2);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(packed.emission[0][c], ascii.emission[0][c], 1e-12);
    EXPECT_NEAR(packed.emission[1][c], ascii.emission[1][c], 1e-12);
  }
  // Without emit_* properties E = 0; an incomplete or mistyped set is an error at its line.
  const Mesh none =
      loadScene(write("none.ply", "ply\nformat ascii 1.0\n" + header + "end_header\n" + vertices +
                                      "3 0 1 2 255 255 255\n3 0 2 3 0 0 0\n"));
  for (const Rgb& e : none.emission) EXPECT_EQ(e, (Rgb{0, 0, 0}));
  expectInputError(
      [&] {
        loadScene(write("part.ply", "ply\nformat ascii 1.0\n" + header +
                                        "property float emit_red\nend_header\n" + vertices +
                                        "3 0 1 2 1 1 1 1\n3 0 2 3 1 1 1 1\n"));
      },
      {"part.ply:12", "emit_red", "emit_blue"});
  expectInputError(
      [&] {
        loadScene(write("int.ply", "ply\nformat ascii 1.0\n" + header +
                                       "property float emit_red\nproperty int emit_green\n"
                                       "property float emit_blue\nend_header\n" +
                                       vertices + "3 0 1 2 1 1 1 1 1 1\n3 0 2 3 1 1 1 1 1 1\n"));
      },
      {"int.ply:13", "emit_green", "'int'"});
}

TEST_F(SceneTest, OffWithAndWithoutFaceColours) {
  const Mesh plain = loadScene(write("p.off",
                                     "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                     "3 0 1 2\n3 0 2 3\n"));
  ASSERT_EQ(plain.triangleCount(), 2);
  EXPECT_EQ(plain.sourceFace, (std::vector<int64_t>{0, 1}));
  EXPECT_NEAR(plain.totalArea(), 1, 1e-12);
  EXPECT_TRUE(hasWarningWith(plain, "no face colours"));

  // OpenMesh reads OFF face colours only under a COFF header (which gives vertex colours too).
  const Mesh coloured = loadScene(write("c.off",
                                        "COFF\n5 2 0\n0 0 0 9 9 9\n1 0 0 9 9 9\n1 1 0 9 9 9\n"
                                        "0 1 0 9 9 9\n2 0 0 9 9 9\n"
                                        "4 0 1 2 3 255 0 0\n3 1 4 2 0 0 255\n"));
  ASSERT_EQ(coloured.triangleCount(), 3);
  EXPECT_EQ(coloured.sourceFace, (std::vector<int64_t>{0, 0, 1}));
  EXPECT_NEAR(coloured.reflectance[0][0], 1, 1e-6);
  EXPECT_NEAR(coloured.reflectance[0][2], 0, 1e-6);
  EXPECT_NEAR(coloured.reflectance[2][2], 1, 1e-6);
  EXPECT_FALSE(hasWarningWith(coloured, "no face colours"));
}

TEST_F(SceneTest, BrokenPlyAndOffAreInputErrors) {
  expectInputError([&] { loadScene(write("g.ply", "not a ply at all\n")); }, {"g.ply"});
  expectInputError([&] { loadScene(write("g.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")); },
                   {"g.off"});
  expectInputError(
      [&] { loadScene(write("n.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")); },
      {"n.off"});
  expectInputError(
      [&] { loadScene(write("big.off", "OFF\n3 1 0\n0 0 0\n1e31 0 0\n0 1 0\n3 0 1 2\n")); },
      {"big.off", "vertex 2"});
}

// Found by tests/fuzz: OpenMesh 9.0 loops forever, reserves without bound or writes out of
// bounds on these, so the reader refuses them before OpenMesh sees them.
TEST_F(SceneTest, MalformedPlyAndOffHeadersAreRefusedBeforeOpenMesh) {
  const std::string ply = "ply\nformat ascii 1.0\n";
  expectInputError([&] { loadScene(write("h1.ply", ply + "element vertex 99999999999\n")); },
                   {"h1.ply", "element count"});
  expectInputError(
      [&] { loadScene(write("h2.ply", ply + "element vertex 3\nproperty float x\n")); },
      {"h2.ply", "end_header"});
  expectInputError([&] { loadScene(write("h3.ply", ply + "property float x\nend_header\n")); },
                   {"h3.ply", "unexpected 'property'"});
  expectInputError(
      [&] {
        loadScene(write("h4.ply", ply + "element face 1\nproperty list int int vertex_indices\n"
                                        "end_header\n2000000000 1 2\n"));
      },
      {"h4.ply", "list count type 'int'"});
  expectInputError([&] { loadScene(write("h.off", "OFF\n4000000000 1 0\n0 0 0\n")); },
                   {"h.off", "vertex count"});
  expectInputError(
      [&] { loadScene(write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n9000 0 1\n")); },
      {"t.off", "face corner count"});
  // A face OpenMesh refuses (repeated corner) used to get its colour written before the array.
  const Mesh mesh = loadScene(write("r.off",
                                    "COFF\n4 2 0\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n"
                                    "1 1 0 1 1 1\n3 0 0 1 255 0 0\n3 1 3 2 0 255 0\n"));
  ASSERT_EQ(mesh.triangleCount(), 1);
  EXPECT_NEAR(mesh.reflectance[0][1], 1, 1e-6);
}

}  // namespace
}  // namespace radiosity
