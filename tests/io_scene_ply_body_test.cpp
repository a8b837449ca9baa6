// PLY and OFF bodies are walked before OpenMesh reads them: counts, value types, face lines and
// indices are checked in ASCII and binary bodies, so that nothing is read silently wrong.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

using namespace std::string_literals;  // "...\0..."s keeps the NUL bytes
using testing::expectInputError;
using testing::hasWarningWith;
using testing::SceneTest;

/// An ASCII PLY file with 4 vertices (lines 13-16) and faces from line 17 with uchar colours.
std::string asciiPly(const std::string& vertices, const std::string& faces, int vertexCount = 4,
                     int faceCount = 2) {
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertexCount) +
         "\nproperty float x\nproperty float y\nproperty float z\n"
         "element face " +
         std::to_string(faceCount) +
         "\nproperty list uchar int vertex_indices\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n" +
         vertices + faces;
}
const std::string kVertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
const std::string kFaces = "3 0 1 2 255 0 0\n3 0 2 3 0 128 255\n";

TEST_F(SceneTest, PlyCountsMustMatchTheBody) {
  ASSERT_EQ(loadScene(write("ok.ply", asciiPly(kVertices, kFaces))).triangleCount(), 2);
  // More faces declared than present: used to give a phantom face.
  expectInputError([&] { loadScene(write("f.ply", asciiPly(kVertices, kFaces, 4, 3))); },
                   {"f.ply:19", "ends after 2 of the 3 faces"});
  // More vertices declared: the first face line is read as a vertex.
  expectInputError([&] { loadScene(write("v.ply", asciiPly(kVertices, kFaces, 5, 2))); },
                   {"v.ply:17", "vertex 4 (counting from 0)", "7 values", "need 3"});
  // More lines than declared.
  expectInputError(
      [&] { loadScene(write("l.ply", asciiPly(kVertices, kFaces + "3 0 1 3 0 0 0\n"))); },
      {"l.ply:19", "more lines than the header declares", "2 faces"});
  // Blank lines and a missing final line end are fine.
  const Mesh blank = loadScene(
      write("b.ply", asciiPly(kVertices + "\n  \n", "3 0 1 2 255 0 0\n\n3 0 2 3 0 128 255")));
  EXPECT_EQ(blank.triangleCount(), 2);
}

TEST_F(SceneTest, PlyValuesMustBeNumbersOfTheirType) {
  const std::string rest = "1 1 0\n0 1 0\n";
  const auto vertex = [&](const std::string& name, const std::string& second) {
    return write(name, asciiPly("0 0 0\n" + second + "\n" + rest, kFaces));
  };
  expectInputError([&] { loadScene(vertex("a.ply", "abc 0 0")); },
                   {"a.ply:14", "'abc' is not a number", "property 'x' of vertex 1"});
  expectInputError([&] { loadScene(vertex("n.ply", "1 nan 0")); },
                   {"n.ply:14", "'nan' is not a finite number", "'y'"});
  expectInputError([&] { loadScene(vertex("i.ply", "1 0 -inf")); },
                   {"i.ply:14", "'-inf' is not a finite number"});
  expectInputError([&] { loadScene(vertex("e.ply", "1e39 0 0")); },
                   {"e.ply:14", "'1e39' is out of the range of type 'float'"});
  expectInputError([&] { loadScene(vertex("d.ply", "1e308 0 0")); },
                   {"d.ply:14", "'1e308'", "'float'"});
  expectInputError([&] { loadScene(vertex("h.ply", "1e999 0 0")); }, {"h.ply:14", "'1e999'"});
  expectInputError([&] { loadScene(vertex("c.ply", "1,5 0 0")); }, {"c.ply:14", "'1,5'"});
  const auto face = [&](const std::string& name, const std::string& second) {
    return write(name, asciiPly(kVertices, "3 0 1 2 255 0 0\n" + second + "\n"));
  };
  expectInputError([&] { loadScene(face("u.ply", "3 0 2 3 0 300 255")); },
                   {"u.ply:18", "'300' is out of the range of type 'uchar' (0 to 255)",
                    "property 'green' of face 1"});
  expectInputError([&] { loadScene(face("m.ply", "3 0 2 3 0 128 -1")); },
                   {"m.ply:18", "'-1'", "'uchar'", "'blue'"});
  expectInputError([&] { loadScene(face("r.ply", "3 0 2 3 0 0.5 255")); },
                   {"r.ply:18", "'0.5' is not an integer", "'uchar'"});
  expectInputError([&] { loadScene(face("q.ply", "3 0 2 3e0 0 0 255")); },
                   {"q.ply:18", "'3e0' is not an integer", "'vertex_indices'"});
  // Exponents and signs are numbers.
  const Mesh wide = loadScene(
      write("w.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
            "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1.5e1 0 0\n+0 1E0 -0.0\n3 0 1 2\n"));
  EXPECT_EQ(wide.vertices[1].x, 15);
}

TEST_F(SceneTest, PlyFaceLinesMustHoldWhatTheirPropertiesNeed) {
  const std::string bare =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
      kVertices;
  // The count says 3, two indices follow.
  expectInputError(
      [&] { loadScene(write("s.ply", bare + "3 0 1\n")); },
      {"s.ply:14", "face 0 (counting from 0) has only 3 values", "'vertex_indices'", "missing"});
  expectInputError([&] { loadScene(write("t.ply", bare + "3 0 1 2 3\n")); },
                   {"t.ply:14", "5 values where its properties need 4"});
  // A custom property missing, or one too many.
  expectInputError(
      [&] { loadScene(write("c.ply", asciiPly(kVertices, "3 0 1 2 255 0\n3 0 2 3 0 0 0\n"))); },
      {"c.ply:17", "has only 6 values", "property 'blue'"});
  expectInputError(
      [&] { loadScene(write("x.ply", asciiPly(kVertices, "3 0 1 2 255 0 0 9\n3 0 2 3 0 0 0\n"))); },
      {"x.ply:17", "8 values where its properties need 7"});
  // Emission missing on a face line.
  const std::string emitting =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
      "property float emit_red\nproperty float emit_green\nproperty float emit_blue\n"
      "end_header\n" +
      kVertices + "3 0 1 2 1 1 1\n3 0 2 3 1 1\n";
  expectInputError([&] { loadScene(write("e.ply", emitting)); },
                   {"e.ply:18", "face 1", "property 'emit_blue'", "missing"});
}

TEST_F(SceneTest, PlyFaceIndicesMustNameVerticesAndFacesNeedThreeCorners) {
  expectInputError(
      [&] { loadScene(write("o.ply", asciiPly(kVertices, "3 0 1 4 0 0 0\n3 0 2 3 0 0 0\n"))); },
      {"o.ply:17", "face 0 (counting from 0): vertex index 4 is out of range", "4 vertices"});
  expectInputError(
      [&] { loadScene(write("n.ply", asciiPly(kVertices, "3 0 1 2 0 0 0\n3 0 -1 3 0 0 0\n"))); },
      {"n.ply:18", "face 1", "vertex index -1 is out of range"});
  expectInputError(
      [&] { loadScene(write("two.ply", asciiPly(kVertices, "2 0 1 0 0 0\n3 0 2 3 0 0 0\n"))); },
      {"two.ply:17", "face 0 (counting from 0) has 2 corners; a face needs at least 3"});
  expectInputError(
      [&] { loadScene(write("zero.ply", asciiPly(kVertices, "0 0 0 0\n3 0 2 3 0 0 0\n"))); },
      {"zero.ply:17", "has 0 corners"});
}

/// A binary little-endian PLY file: 4 float vertices, the given faces (int indices, no colour).
std::string binaryPly(const std::vector<std::vector<int32_t>>& faces, size_t declaredFaces) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\nelement face " +
      std::to_string(declaredFaces) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f})
    out.append(reinterpret_cast<const char*>(&v), 4);  // the test hosts are little-endian
  for (const auto& face : faces) {
    out += static_cast<char>(face.size());
    for (int32_t i : face) out.append(reinterpret_cast<const char*>(&i), 4);
  }
  return out;
}

TEST_F(SceneTest, BinaryPlyBodiesAreCheckedByElement) {
  EXPECT_EQ(loadScene(write("ok.ply", binaryPly({{0, 1, 2}, {0, 2, 3}}, 2))).triangleCount(), 2);
  expectInputError(
      [&] {
        loadScene(write("f.ply", binaryPly({{0, 1, 2}, {0, 2, 3}}, 3)));
      },
      {"f.ply: face 2 (counting from 0)", "ends inside it", "shorter"});
  expectInputError(
      [&] {
        loadScene(write("l.ply", binaryPly({{0, 1, 2}, {0, 2, 3}}, 1)));
      },
      {"l.ply: 13 bytes after the last element", "longer"});
  expectInputError(
      [&] {
        loadScene(write("o.ply", binaryPly({{0, 1, 2}, {0, 2, 4}}, 2)));
      },
      {"o.ply: face 1 (counting from 0): vertex index 4 is out of range"});
  expectInputError(
      [&] {
        loadScene(write("n.ply", binaryPly({{0, -1, 2}}, 1)));
      },
      {"n.ply: face 0", "vertex index -1"});
  expectInputError(
      [&] {
        loadScene(write("two.ply", binaryPly({{0, 1}}, 1)));
      },
      {"two.ply: face 0", "2 corners"});
  std::string nan = binaryPly({{0, 1, 2}}, 1);
  const float bad = std::nanf("");
  nan.replace(nan.find("end_header\n") + 11 + 4, 4, reinterpret_cast<const char*>(&bad), 4);
  expectInputError([&] { loadScene(write("nan.ply", nan)); },
                   {"nan.ply: vertex 0 (counting from 0)", "'y' is not a finite number"});
}

TEST_F(SceneTest, ValidPlyWithCommentsAndEmissionLoadsAsBefore) {
  const std::string body = kVertices + "3 0 1 2 255 0 51 1.5 2.25 40\n3 0 2 3 0 102 255 0 0 0\n";
  const std::string header =
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property float emit_red\nproperty float emit_green\nproperty float emit_blue\n"
      "end_header\n";
  const Mesh plain = loadScene(write("p.ply", "ply\nformat ascii 1.0\n" + header + body));
  std::string crlf;  // CRLF line ends, comments and a trailing blank line
  for (char c : "ply\nformat ascii 1.0\ncomment made by hand\n" + header + body + "\n") {
    crlf += c == '\n' ? "\r\n" : std::string(1, c);
  }
  const Mesh commented = loadScene(write("c.ply", crlf));
  ASSERT_EQ(plain.triangleCount(), 2);
  EXPECT_EQ(commented.vertices, plain.vertices);
  EXPECT_EQ(commented.triangles, plain.triangles);
  EXPECT_EQ(commented.reflectance, plain.reflectance);
  EXPECT_EQ(commented.emission, plain.emission);
  EXPECT_EQ(plain.emission[0], (Rgb{1.5, 2.25, 40}));
  EXPECT_NEAR(plain.reflectance[0][2], 0.2, 1e-6);
  EXPECT_NEAR(plain.reflectance[1][1], 0.4, 1e-6);
}

TEST_F(SceneTest, OffFacesNeedThreeCornersAndCommentsAreFine) {
  expectInputError(
      [&] { loadScene(write("two.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n")); },
      {"two.off:7", "face 1 (counting from 0) has 2 corners"});
  expectInputError([&] { loadScene(write("o.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")); },
                   {"o.off:6", "vertex index 3 is out of range"});
  expectInputError(
      [&] { loadScene(write("m.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n")); },
      {"m.off:7", "more faces than the header declares"});
  expectInputError(
      [&] { loadScene(write("c.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n")); },
      {"c.off:6", "COFF"});
  const Mesh plain = loadScene(write("p.off",
                                     "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"
                                     "4 0 1 2 3\n3 0 1 4\n"));
  const Mesh commented = loadScene(write("q.off",
                                         "OFF\n# a quad and a triangle\n5 2 0 # counts\n"
                                         "0 0 0\n1 0 0 # second\n\n1 1 0\n#\n0 1 0\n0.5 0.5 1\n"
                                         "  # faces\n4 0 1 2 3\n3 0 1 4 # last\n# end\n"));
  ASSERT_EQ(plain.triangleCount(), 3);
  EXPECT_EQ(commented.vertices, plain.vertices);
  EXPECT_EQ(commented.triangles, plain.triangles);
  EXPECT_EQ(commented.sourceFace, plain.sourceFace);
  // Comments in a COFF file keep its colours.
  const Mesh coloured = loadScene(write("c2.off",
                                        "COFF\n# coloured\n3 1 0\n0 0 0 9 9 9\n1 0 0 9 9 9 # v\n"
                                        "0 1 0 9 9 9\n3 0 1 2 255 0 0 # red\n"));
  ASSERT_EQ(coloured.triangleCount(), 1);
  EXPECT_NEAR(coloured.reflectance[0][0], 1, 1e-6);
  EXPECT_NEAR(coloured.reflectance[0][1], 0, 1e-6);
  EXPECT_FALSE(hasWarningWith(coloured, "no face colours"));
}

// PLY double coordinates keep every bit (OpenMesh 9 reads them through float).
TEST_F(SceneTest, DoublePlyCoordinatesKeepEveryBit) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const Mesh mesh = loadScene(
      write("d.ply", header + "0.1 0 0\n1.0000000001 0 1e-40\n0 1 0.30000000000000004\n3 0 1 2\n"));
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[0].x, 0.1);
  EXPECT_EQ(mesh.vertices[1].x, 1.0000000001);
  EXPECT_EQ(mesh.vertices[1].z, 1e-40);
  EXPECT_EQ(mesh.vertices[2].z, 0.30000000000000004);
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (double v : {0.1, 0.0, 0.0, 1.0000000001, 0.0, 1e-40, 0.0, 1.0, 0.30000000000000004})
    binary.append(reinterpret_cast<const char*>(&v), 8);
  binary += static_cast<char>(3);
  for (int32_t i : {0, 1, 2}) binary.append(reinterpret_cast<const char*>(&i), 4);
  EXPECT_EQ(loadScene(write("b.ply", binary)).vertices, mesh.vertices);
}

// Indices in a list of floats are read as numbers: one beyond any integer (found by the fuzzer:
// its conversion to an integer for the message was undefined) is refused, and shown as read.
TEST_F(SceneTest, BinaryPlyIndexBeyondAnyIntegerIsRefused) {
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list uchar float vertex_indices\nend_header\n";
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0})
    binary.append(reinterpret_cast<const char*>(&v), 8);
  binary += static_cast<char>(3);
  for (float i : {0.0f, 1.0f, 4.7e30f}) binary.append(reinterpret_cast<const char*>(&i), 4);
  expectInputError([&] { loadScene(write("huge.ply", binary)); },
                   {"huge.ply", "vertex index 4.7e+30 is out of range"});
}

// A triangle that names a vertex twice has no area: dropped with a warning, as in OBJ, and the
// faces after it keep their own numbers and materials. A larger face that repeats a corner is
// refused: its outline is ambiguous.
TEST_F(SceneTest, PlyAndOffFacesRepeatingACorner) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 3\nproperty list uchar int vertex_indices\n"
      "property float emit_red\nproperty float emit_green\nproperty float emit_blue\n"
      "end_header\n";
  const Mesh mesh = loadScene(
      write("r.ply", header + kVertices + "3 0 1 1 5 5 5\n3 0 1 2 7 7 7\n3 0 2 3 9 9 9\n"));
  ASSERT_EQ(mesh.triangleCount(), 2);
  EXPECT_EQ(mesh.sourceFace, (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(mesh.emission[0], (Rgb{7, 7, 7}));
  EXPECT_EQ(mesh.emission[1], (Rgb{9, 9, 9}));
  EXPECT_TRUE(hasWarningWith(mesh, "r.ply:17: dropped 1 face(s) that name a vertex twice"));
  EXPECT_FALSE(hasWarningWith(mesh, "OpenMesh"));
  expectInputError(
      [&] { loadScene(write("q.ply", asciiPly(kVertices, "4 0 1 2 1 0 0 0\n3 0 2 3 0 0 0\n"))); },
      {"q.ply:17", "face 0 (counting from 0)", "vertex 1 twice"});
  const Mesh binary = loadScene(write("rb.ply", binaryPly({{0, 2, 2}, {0, 1, 2}}, 2)));
  EXPECT_EQ(binary.sourceFace, (std::vector<int64_t>{1}));
  EXPECT_TRUE(hasWarningWith(binary, "rb.ply: dropped 1 face(s) that name a vertex twice"));
  expectInputError(
      [&] {
        loadScene(write("qb.ply", binaryPly({{0, 1, 0, 2}}, 1)));
      },
      {"qb.ply: face 0 (counting from 0)", "vertex 0 twice"});
  const Mesh off = loadScene(write("r.off",
                                   "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                   "3 3 3 1\n4 0 1 2 3\n"));
  EXPECT_EQ(off.triangleCount(), 2);
  EXPECT_EQ(off.sourceFace, (std::vector<int64_t>{1, 1}));
  EXPECT_TRUE(hasWarningWith(off, "r.off:7: dropped 1 face(s) that name a vertex twice"));
  expectInputError(
      [&] {
        loadScene(write("q.off",
                        "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                        "4 0 1 3 3\n"));
      },
      {"q.off:7", "face 0 (counting from 0)", "vertex 3 twice"});
}

// A plain OFF vertex line holds x y z and nothing else (colours need COFF, normals NOFF).
TEST_F(SceneTest, PlainOffVertexLinesHoldThreeValues) {
  expectInputError(
      [&] {
        loadScene(write("x.off",
                        "OFF\n3 1 0\n0 0 0\n1 0 0 0.5\n0 1 0\n"
                        "3 0 1 2\n"));
      },
      {"x.off:4", "vertex 1 (counting from 0) has 4 values", "COFF"});
  expectInputError([&] { loadScene(write("y.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n")); },
                   {"y.off:4", "vertex 1 (counting from 0) has 2 values"});
}

// OpenMesh stores a float colour as a byte, ×255 modulo 256: 200 (the 0–255 convention) became
// ρ = 0.2196 and 1.5 became 0.494, without a word; a Kd of 1.2 in an MTL is refused.
TEST_F(SceneTest, PlyFloatColoursOutsideZeroToOneAreRefused) {
  auto floatColours = [](const std::string& faces) {
    return "ply\nformat ascii 1.0\nelement vertex 4\n"
           "property float x\nproperty float y\nproperty float z\nelement face 2\n"
           "property list uchar int vertex_indices\n"
           "property float red\nproperty float green\nproperty float blue\nend_header\n" +
           kVertices + faces;
  };
  const Mesh fractions =
      loadScene(write("f.ply", floatColours("3 0 1 2 1 0 0.5\n3 0 2 3 0 0.25 1\n")));
  // As the file writes them: OpenMesh passes them through a byte (0.5 became 0.498).
  EXPECT_EQ(fractions.reflectance[0], (Rgb{1, 0, 0.5}));
  EXPECT_EQ(fractions.reflectance[1], (Rgb{0, 0.25, 1}));
  expectInputError(
      [&] { loadScene(write("b.ply", floatColours("3 0 1 2 200 200 200\n3 0 2 3 0 0 0\n"))); },
      {"b.ply:17:", "face 0 (counting from 0)", "'red' is 200", "outside [0, 1]"});
  expectInputError(
      [&] { loadScene(write("h.ply", floatColours("3 0 1 2 1 0 0\n3 0 2 3 0.5 1.5 0\n"))); },
      {"h.ply:18:", "face 1 (counting from 0)", "'green' is 1.5"});
  expectInputError(
      [&] { loadScene(write("n.ply", floatColours("3 0 1 2 1 0 -0.1\n3 0 2 3 0 0 0\n"))); },
      {"n.ply:17:", "'blue' is -0.1"});
  // uchar colours are 0–255, divided by 255.
  const Mesh bytes =
      loadScene(write("u.ply", asciiPly(kVertices, "3 0 1 2 200 0 0\n3 0 2 3 0 0 0\n")));
  EXPECT_NEAR(bytes.reflectance[0][0], 200.0 / 255, 1e-6);

  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty float red\nproperty float green\n"
      "property float blue\nend_header\n";
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f})
    binary.append(reinterpret_cast<const char*>(&v), 4);
  binary += static_cast<char>(3);
  for (int32_t i : {0, 1, 2}) binary.append(reinterpret_cast<const char*>(&i), 4);
  for (float v : {0.5f, 255.f, 0.f}) binary.append(reinterpret_cast<const char*>(&v), 4);
  expectInputError([&] { loadScene(write("bin.ply", binary)); },
                   {"bin.ply: face 0 (counting from 0)", "'green' is 255", "outside [0, 1]"});
}

// obj_info is a standard PLY header line (text for the reader, as comment is): it used to be
// refused as "unexpected 'obj_info'".
TEST_F(SceneTest, PlyObjInfoLinesAreReadLikeComments) {
  const std::string plain = asciiPly(kVertices, kFaces);
  std::string info = plain;
  info.insert(info.find("element vertex"), "obj_info scanned 2024\nobj_info num_cols 1\n");
  const Mesh a = loadScene(write("p.ply", plain));
  const Mesh b = loadScene(write("i.ply", info));
  ASSERT_EQ(b.triangleCount(), 2);
  EXPECT_EQ(b.vertices, a.vertices);
  EXPECT_EQ(b.triangles, a.triangles);
  EXPECT_EQ(b.reflectance, a.reflectance);
  EXPECT_EQ(b.warnings, a.warnings);  // no "unsupported keyword" from OpenMesh
}

// The counts on the header line ("OFF 4 2 0") used to be taken from the first vertex's line:
// "more faces than the header declares (0)". They are read there now.
TEST_F(SceneTest, OffCountsOnTheHeaderLineAreRead) {
  const std::string body = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  const Mesh twoLines = loadScene(write("a.off", "OFF\n4 2 0\n" + body));
  const Mesh oneLine = loadScene(write("b.off", "OFF 4 2 0\n" + body));
  const Mesh commented = loadScene(write("c.off", "OFF 4 2 0 # counts\n" + body));
  ASSERT_EQ(twoLines.triangleCount(), 2);
  for (const Mesh* m : {&oneLine, &commented}) {
    EXPECT_EQ(m->vertices, twoLines.vertices);
    EXPECT_EQ(m->triangles, twoLines.triangles);
  }
  expectInputError([&] { loadScene(write("d.off", "OFF 4 2\n" + body)); },
                   {"d.off", "header line 'OFF 4 2'", "vertex, face and edge counts"});
  expectInputError([&] { loadScene(write("e.off", "OFFX\n4 2 0\n" + body)); },
                   {"e.off", "header line 'OFFX'"});
}

// Binary OFF is read as OpenMesh writes it (little-endian, nothing after a face's indices);
// Geomview's (big-endian, a colour count per face) used to be refused with a count read the
// wrong way round ("vertex count 67108864 exceeds the file's size") or "face 1 has 0 corners".
TEST_F(SceneTest, BinaryOffSaysWhichLayoutItReads) {
  auto binaryOff = [](bool bigEndian, bool colourCount) {
    std::string out = "OFF BINARY\n";
    auto put = [&](uint32_t bits) {
      for (int k = 0; k < 4; ++k)
        out += static_cast<char>(bits >> (bigEndian ? 24 - 8 * k : 8 * k) & 0xff);
    };
    auto putFloat = [&](float f) {
      uint32_t bits = 0;
      std::memcpy(&bits, &f, 4);
      put(bits);
    };
    for (uint32_t c : {4u, 2u, 0u}) put(c);
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) putFloat(v);
    for (const auto& face : {std::array<uint32_t, 3>{0, 1, 2}, std::array<uint32_t, 3>{0, 2, 3}}) {
      put(3);
      for (uint32_t i : face) put(i);
      if (colourCount) put(0);
    }
    return out;
  };
  EXPECT_EQ(loadScene(write("le.off", binaryOff(false, false))).triangleCount(), 2);
  expectInputError([&] { loadScene(write("be.off", binaryOff(true, true))); },
                   {"be.off", "big-endian byte order", "convert it to text OFF or to PLY"});
  expectInputError([&] { loadScene(write("gv.off", binaryOff(false, true))); },
                   {"gv.off", "nothing after a face's vertex indices"});
}

}  // namespace
}  // namespace radiosity
