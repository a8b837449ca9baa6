// STL files, binary and ASCII: the same cube read from either and from an OBJ, exact ASCII
// coordinates, solids as labels, facets OpenMesh skips or cannot attach, and every refusal of
// the strict walk as an input error naming the file (and the line for ASCII).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

using testing::closedAndOriented;
using testing::expectInputError;
using testing::expectNear;
using testing::hasWarningWith;
using testing::SceneTest;
using testing::signedVolume;

using Facet = std::array<Vec3, 3>;

/// The 12 facets of the cube [lo, lo + size]³, wound to face outward (counter-clockwise seen
/// from outside), two per side.
std::vector<Facet> cube(double lo = 0, double size = 1) {
  const double a = lo, b = lo + size;
  const std::vector<std::array<Vec3, 4>> sides = {
      {{{a, a, a}, {a, a, b}, {a, b, b}, {a, b, a}}},  // -x
      {{{b, a, a}, {b, b, a}, {b, b, b}, {b, a, b}}},  // +x
      {{{a, a, a}, {b, a, a}, {b, a, b}, {a, a, b}}},  // -y
      {{{a, b, a}, {a, b, b}, {b, b, b}, {b, b, a}}},  // +y
      {{{a, a, a}, {a, b, a}, {b, b, a}, {b, a, a}}},  // -z
      {{{a, a, b}, {b, a, b}, {b, b, b}, {a, b, b}}},  // +z
  };
  std::vector<Facet> facets;
  for (const auto& q : sides) {
    facets.push_back({q[0], q[1], q[2]});
    facets.push_back({q[0], q[2], q[3]});
  }
  return facets;
}

/// "%.17g": the double itself.
std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

/// An ASCII STL of one solid, one keyword a line: facet f's `vertex` lines are 4 + 7f … 6 + 7f.
std::string asciiStl(const std::vector<Facet>& facets, const std::string& name = "cube") {
  std::string text = "solid " + name + "\n";
  for (const Facet& f : facets) {
    text += "  facet normal 0 0 0\n    outer loop\n";
    for (const Vec3& v : f) {
      text.append("      vertex ")
          .append(number(v.x))
          .append(" ")
          .append(number(v.y))
          .append(" ")
          .append(number(v.z))
          .append("\n");
    }
    text += "    endloop\n  endfacet\n";
  }
  return text + "endsolid " + name + "\n";
}

void appendFloat(std::string& bytes, float value) {
  bytes.append(reinterpret_cast<const char*>(&value), 4);  // the test hosts are little-endian
}

/// A binary STL: the 80-byte header (`header`, padded with NULs), the facet count, then each
/// facet's normal (0 0 0), corners and two attribute bytes.
std::string binaryStl(const std::vector<Facet>& facets, const std::string& header = "") {
  std::string bytes = header;
  bytes.resize(80, '\0');
  const auto n = static_cast<uint32_t>(facets.size());
  bytes.append(reinterpret_cast<const char*>(&n), 4);
  for (const Facet& f : facets) {
    for (int k = 0; k < 3; ++k) appendFloat(bytes, 0);
    for (const Vec3& v : f) {
      for (int k = 0; k < 3; ++k) appendFloat(bytes, static_cast<float>(v[k]));
    }
    bytes.append(2, '\0');
  }
  return bytes;
}

/// The same facets as an OBJ, its vertices in the order of their first use (as STL's are).
std::string objOf(const std::vector<Facet>& facets) {
  std::vector<Vec3> vertices;
  std::string faces;
  for (const Facet& f : facets) {
    faces += "f";
    for (const Vec3& v : f) {
      size_t i = 0;
      while (i < vertices.size() && !(vertices[i] == v)) ++i;
      if (i == vertices.size()) vertices.push_back(v);
      faces.append(" ").append(std::to_string(i + 1));
    }
    faces += "\n";
  }
  std::string text;
  for (const Vec3& v : vertices)
    text.append("v ")
        .append(number(v.x))
        .append(" ")
        .append(number(v.y))
        .append(" ")
        .append(number(v.z) + "\n");
  return text + faces;
}

/// The same vertices, triangles in the same order, areas and normals.
void expectSameMesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.triangleCount(), b.triangleCount());
  for (int64_t t = 0; t < a.triangleCount(); ++t) {
    EXPECT_EQ(a.area(t), b.area(t));
    expectNear(a.normal(t), b.normal(t), 0);
  }
}

TEST_F(SceneTest, StlAsciiAndBinaryCubesReadAsTheObjCube) {
  const std::vector<Facet> facets = cube();
  const Mesh ascii = loadScene(write("cube.stl", asciiStl(facets)));
  const Mesh binary = loadScene(write("cube_b.stl", binaryStl(facets)));
  const Mesh obj = loadScene(write("cube.obj", objOf(facets)));
  ASSERT_EQ(ascii.triangleCount(), 12);
  EXPECT_EQ(ascii.vertices.size(), 8u);
  expectSameMesh(ascii, obj);
  expectSameMesh(binary, obj);
  EXPECT_TRUE(closedAndOriented(ascii));
  EXPECT_NEAR(signedVolume(ascii), 1, 1e-12);  // outward: positive
  expectNear(ascii.normal(0), {-1, 0, 0});
  EXPECT_NEAR(ascii.totalArea(), 6, 1e-12);
  // Each triangle is its facet, with the default material and the file's label.
  for (int64_t t = 0; t < 12; ++t) {
    EXPECT_EQ(ascii.sourceFace[t], t);
    EXPECT_EQ(binary.sourceFace[t], t);
    EXPECT_EQ(ascii.reflectance[t], detail::kDefaultReflectance);
    EXPECT_EQ(ascii.emission[t], (Rgb{0, 0, 0}));
  }
  EXPECT_EQ(ascii.labelNames, (std::vector<std::string>{"cube"}));
  EXPECT_EQ(binary.labelNames, (std::vector<std::string>{"cube_b.stl"}));
  EXPECT_EQ(binary.label, std::vector<int32_t>(12, 0));
  EXPECT_TRUE(hasWarningWith(ascii, "cube.stl: no materials in STL; every facet gets ρ = 0.5"));
  EXPECT_TRUE(hasWarningWith(binary, "no materials in STL"));
  EXPECT_EQ(ascii.warnings.size(), 1u);
  // The extension in any case.
  EXPECT_EQ(loadScene(write("CUBE.STL", asciiStl(facets))).triangleCount(), 12);
}

TEST_F(SceneTest, StlAsciiKeepsTheFileDoubles) {
  // 0.1 and 1.3 are not floats: OpenMesh reads them as floats, the walk's values are kept.
  const std::vector<Facet> facets = cube(0.1, 1.2);
  const Mesh ascii = loadScene(write("c.stl", asciiStl(facets)));
  const Mesh obj = loadScene(write("c.obj", objOf(facets)));
  expectSameMesh(ascii, obj);
  EXPECT_EQ(ascii.vertices[0], (Vec3{0.1, 0.1, 0.1}));
  EXPECT_EQ(ascii.vertices[0].x, 0.1);
  EXPECT_EQ(ascii.vertices[2].z, 0.1 + 1.2);
  // Binary files hold floats: the same corners as floats, widened.
  const Mesh binary = loadScene(write("c_b.stl", binaryStl(facets)));
  EXPECT_EQ(binary.vertices[0].x, static_cast<double>(0.1f));
  EXPECT_EQ(binary.triangles, ascii.triangles);
}

TEST_F(SceneTest, StlAsciiTakesAnyWhitespaceAndKeywordCase) {
  const std::vector<Facet> facets = cube();
  // One line, tabs, keywords in mixed case, a name with spaces ("outer" in it: OpenMesh's own
  // reader takes any line holding "outer" as the start of a loop), numbers as +1, 1., 1e0.
  std::string text = "  \n\tSOLID  outer wall  ";
  for (const Facet& f : facets) {
    text += "Facet\tNormal 0 0 -0 OUTER Loop ";
    for (const Vec3& v : f) {
      text += "Vertex";
      for (int k = 0; k < 3; ++k) text += v[k] == 1 ? " +1.\t" : " 0e0 ";
    }
    text += "EndLoop endFacet ";
  }
  text += "\r\nENDSOLID outer wall\r\n\n";
  const Mesh mesh = loadScene(write("w.stl", text));
  expectSameMesh(mesh, loadScene(write("w.obj", objOf(facets))));
  EXPECT_EQ(mesh.labelNames, (std::vector<std::string>{"outer wall"}));
}

TEST_F(SceneTest, StlBinaryWhoseHeaderBeginsWithSolid) {
  const std::vector<Facet> facets = cube();
  const Mesh mesh = loadScene(write("s.stl", binaryStl(facets, "solid cube exported by a CAD")));
  expectSameMesh(mesh, loadScene(write("s.obj", objOf(facets))));
}

TEST_F(SceneTest, StlSolidsBecomeLabels) {
  const std::vector<Facet> facets = cube();
  const std::vector<Facet> floor(facets.begin() + 8, facets.begin() + 10);  // -z
  const std::vector<Facet> walls(facets.begin(), facets.begin() + 8);
  const std::vector<Facet> roof(facets.begin() + 10, facets.end());  // +z
  const std::vector<Facet> other = cube(5);
  const std::vector<Facet> otherRoof(other.begin() + 10, other.end());
  // Two solids named floor: one label; a solid without a name: the file's name.
  const std::string text = asciiStl(floor, "floor") + asciiStl(walls, "hot walls") +
                           asciiStl(roof, "floor") + "solid\nendsolid\n" + asciiStl(otherRoof, "");
  const Mesh mesh = loadScene(write("room.stl", text));
  ASSERT_EQ(mesh.triangleCount(), 14);
  EXPECT_EQ(mesh.labelNames, (std::vector<std::string>{"floor", "hot walls", "room.stl"}));
  std::vector<int32_t> labels(2, 0);
  labels.resize(10, 1);
  labels.resize(12, 0);
  labels.resize(14, 2);
  EXPECT_EQ(mesh.label, labels);
  for (int64_t t = 0; t < 14; ++t) EXPECT_EQ(mesh.sourceFace[t], t);
}

TEST_F(SceneTest, StlFacetWithTwoEqualCornersIsDroppedWithOneWarning) {
  std::vector<Facet> facets = cube();
  facets.insert(facets.begin() + 1, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 0}});
  facets.insert(facets.begin() + 5, {Vec3{1, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 1, 1}});
  for (const std::string& name : {std::string("d.stl"), std::string("d_b.stl")}) {
    const Mesh mesh =
        loadScene(write(name, name == "d.stl" ? asciiStl(facets) : binaryStl(facets, "solid d")));
    ASSERT_EQ(mesh.triangleCount(), 12);
    EXPECT_EQ(mesh.sourceFace[0], 0);
    EXPECT_EQ(mesh.sourceFace[1], 2);  // later facets keep their numbers
    EXPECT_EQ(mesh.sourceFace[11], 13);
    EXPECT_TRUE(closedAndOriented(mesh));
    // file:line of the first (line 9: facet 1's `facet`) for ASCII; the file for binary.
    const std::string where = name == "d.stl" ? "d.stl:9: " : "d_b.stl: ";
    EXPECT_TRUE(hasWarningWith(
        mesh, where + "dropped 2 facet(s) with two equal corners (no area), the first facet 1"));
  }
}

TEST_F(SceneTest, StlFacetsAtANonManifoldEdge) {
  // Three facets share the edge (0,0,0)-(1,0,0): OpenMesh cannot attach the third and adds copies
  // of its corners; the mesh keeps the file's corners, as an OBJ of the same facets does.
  const std::vector<Facet> facets = {
      {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}},
      {Vec3{1, 0, 0}, Vec3{0, 0, 0}, Vec3{0, -1, 0}},
      {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 1}},
      {Vec3{1, 0, 0}, Vec3{2, 1, 0}, Vec3{0, 1, 0}},
  };
  for (const std::string& name : {std::string("m.stl"), std::string("m_b.stl")}) {
    ::testing::internal::CaptureStderr();
    const Mesh mesh =
        loadScene(write(name, name == "m.stl" ? asciiStl(facets) : binaryStl(facets)));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");  // OpenMesh prints nothing
    expectSameMesh(mesh, loadScene(write("m.obj", objOf(facets))));
    EXPECT_EQ(mesh.vertices.size(), 6u);
    EXPECT_EQ(mesh.triangles[2], (Triangle{0, 1, 4}));
    EXPECT_EQ(mesh.triangles[3], (Triangle{1, 5, 2}));
    EXPECT_FALSE(hasWarningWith(mesh, "OpenMesh"));
  }
}

TEST_F(SceneTest, StlCornersEqualAsFloatsAreJoinedWithAWarning) {
  // 1.00000001 and 1.00000002 are the same float: OpenMesh makes them one vertex, at the first.
  const std::string text =
      "solid j\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1.00000001 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\n"
      "vertex 0 -1 0\nvertex 1.00000002 0 0\nendloop\nendfacet\nendsolid j\n";
  const Mesh mesh = loadScene(write("j.stl", text));
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[1].x, 1.00000001);
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 3, 1}));
  EXPECT_TRUE(hasWarningWith(
      mesh, "j.stl:13: 1 corner(s) equal an earlier corner in float precision but not exactly"));
}

TEST_F(SceneTest, StlWhereOpenMeshJoinsOtherwiseItsFloatsAreUsedWithAWarning) {
  // ±1e-38 (below FLT_MIN) are one corner for the walk, two for OpenMesh (which joins values
  // at most FLT_MIN apart): OpenMesh's vertices are kept, and the user told.
  const std::string text =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 1e-38 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 -1\nouter loop\nvertex -1e-38 0 0\n"
      "vertex 0 -1 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n";
  const Mesh mesh = loadScene(write("t.stl", text));
  ASSERT_EQ(mesh.vertices.size(), 5u);
  EXPECT_EQ(mesh.vertices[3].x, static_cast<double>(-1e-38f));
  EXPECT_EQ(mesh.triangles[1], (Triangle{3, 4, 1}));
  EXPECT_TRUE(hasWarningWith(mesh, "t.stl: OpenMesh read the file otherwise than its strict walk"));
}

TEST_F(SceneTest, StlBinaryRefusals) {
  const std::string good = binaryStl(cube());
  expectInputError([&] { loadScene(write("e.stl", "")); },
                   {"e.stl: not an STL file", "this file has 0 bytes", "begins with 'solid'"});
  expectInputError([&] { loadScene(write("short.stl", good.substr(0, good.size() - 10))); },
                   {"short.stl: not an STL file", "84 + 50 × facets bytes",
                    "has " + std::to_string(good.size() - 10) + " bytes and says 12 facets"});
  expectInputError([&] { loadScene(write("long.stl", good + "x")); },
                   {"long.stl: not an STL file", "and says 12 facets"});
  // A truncated binary file whose header begins with "solid" is taken for ASCII, and told.
  const std::string solid = binaryStl(cube(), "solid cube");
  expectInputError([&] { loadScene(write("ts.stl", solid.substr(0, solid.size() - 1))); },
                   {"ts.stl:1: ", "binary", "84 + 50 × facets bytes", "says 12 facets"});
  expectInputError([&] { loadScene(write("z.stl", binaryStl({}))); },
                   {"z.stl: binary STL with no facets"});
  std::vector<Facet> facets = cube();
  facets[3][1].y = std::nan("");
  expectInputError([&] { loadScene(write("nan.stl", binaryStl(facets))); },
                   {"nan.stl: facet 3 (counting from 0), corner 2 of 3: coordinate nan"});
  facets = cube();
  facets[5][2].z = 1e31;  // a float, beyond 1e30
  expectInputError([&] { loadScene(write("big.stl", binaryStl(facets))); },
                   {"big.stl: facet 5", "corner 3", "|x| ≤ 1e30"});
  facets[5][2].z = HUGE_VAL;
  expectInputError([&] { loadScene(write("inf.stl", binaryStl(facets))); },
                   {"inf.stl: facet 5", "coordinate inf"});
  // The normal is not looked at.
  std::string nanNormal = binaryStl(cube());
  const float nan = std::nanf("");
  nanNormal.replace(84, 4, reinterpret_cast<const char*>(&nan), 4);
  EXPECT_EQ(loadScene(write("nn.stl", nanNormal)).triangleCount(), 12);
}

TEST_F(SceneTest, StlAsciiRefusalsNameTheLine) {
  const std::string good = asciiStl(cube());
  // Replaces the first `from` in the good cube (facet 0's lines are 2 to 8, facet 1's 9 to 15).
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  expectInputError([&] { loadScene(write("x.stl", "hello\n")); },
                   {"x.stl: not an STL file", "has 6 bytes", "begins with 'solid'"});
  expectInputError([&] { loadScene(write("n.stl", with("vertex 0 0 1", "vertex 0 nan 1"))); },
                   {"n.stl:5: ", "coordinate nan", "finite"});
  expectInputError([&] { loadScene(write("b.stl", with("vertex 0 0 1", "vertex 0 1e31 1"))); },
                   {"b.stl:5: ", "coordinate 1e31", "|x| ≤ 1e30"});
  expectInputError([&] { loadScene(write("r.stl", with("vertex 0 0 1", "vertex 0 1e400 1"))); },
                   {"r.stl:5: ", "coordinate 1e400"});
  expectInputError([&] { loadScene(write("s.stl", with("vertex 0 0 1", "vertex 0 1e5x 1"))); },
                   {"s.stl:5: ", "'1e5x' is not a number (expected 'vertex x y z')"});
  expectInputError([&] { loadScene(write("m.stl", with("vertex 0 0 1\n", "vertex 0 0\n"))); },
                   {"m.stl:6: ", "'vertex' is not a number"});
  expectInputError([&] { loadScene(write("4.stl", with("endloop", "vertex 0 0 2\nendloop"))); },
                   {"4.stl:7: ", "a 4th vertex", "STL facets are triangles"});
  expectInputError([&] { loadScene(write("2.stl", with("vertex 0 1 1\n", ""))); },
                   {"2.stl:6: ", "expected 'vertex x y z', found 'endloop'"});
  expectInputError([&] { loadScene(write("o.stl", with("outer loop", "outer"))); },
                   {"o.stl:4: ", "expected 'outer loop', found 'vertex'"});
  expectInputError([&] { loadScene(write("f.stl", with("facet normal 0 0 0", "facet 0 0 0"))); },
                   {"f.stl:2: ", "expected 'facet normal nx ny nz', found '0'"});
  expectInputError([&] { loadScene(write("nn.stl", with("normal 0 0 0", "normal 0 x 0"))); },
                   {"nn.stl:2: ", "expected 'facet normal nx ny nz', found 'x'"});
  expectInputError([&] { loadScene(write("k.stl", with("endfacet", "endfact"))); },
                   {"k.stl:8: ", "expected 'endfacet', found 'endfact'"});
  expectInputError([&] { loadScene(write("w.stl", with("  facet normal", "  fact normal"))); },
                   {"w.stl:2: ", "expected 'facet normal nx ny nz' or 'endsolid', found 'fact'"});
  // Not closed: the line of the solid. The unclosed one is the second, on line 87.
  const std::string facets = good.substr(11, good.size() - 11 - 14);  // no solid, endsolid
  expectInputError([&] { loadScene(write("u.stl", good + "solid two\n" + facets)); },
                   {"u.stl:87: ", "the solid 'two' begun here has no 'endsolid'"});
  expectInputError([&] { loadScene(write("u2.stl", "solid\n")); },
                   {"u2.stl:1: ", "the solid begun here has no 'endsolid'"});
  expectInputError([&] { loadScene(write("t.stl", good.substr(0, good.rfind("    endloop")))); },
                   {"t.stl:83: ", "expected 'endloop', found the end of the file"});
  // Nothing but whitespace or another solid after endsolid.
  expectInputError([&] { loadScene(write("j.stl", good + "\n junk\n")); },
                   {"j.stl:88: ", "only another 'solid' or the end of the file may follow"});
  expectInputError([&] { loadScene(write("z.stl", "solid empty\nendsolid empty\n")); },
                   {"z.stl: no facets"});
  // A binary byte in an ASCII file is shown escaped.
  expectInputError([&] { loadScene(write("c.stl", with("endloop", "end\x01loop"))); },
                   {"c.stl:7: ", "found 'end\\x01loop'"});
  // Normals are not looked at but for their syntax: nan (some exporters' for no area) is fine.
  EXPECT_EQ(
      loadScene(write("nan.stl", with("normal 0 0 0", "normal nan -nan inf"))).triangleCount(), 12);
}

}  // namespace
}  // namespace radiosity
