// OBJ and MTL files: the reader (materials, labels, polygons, tolerated and ignored syntax, and
// errors that name the file and line to fix) and the writer, whose files read back identically.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using namespace std::string_literals;  // "...\0..."s keeps the NUL bytes
using testing::expectInputError;
using testing::expectNear;
using testing::hasWarningWith;
using testing::SceneTest;

TEST_F(SceneTest, ObjWithMaterialsReadsKdAndKe) {
  write("mat.mtl", "newmtl wall\nKd 0.25 0.5 0.75\n\nnewmtl lamp\nKd 0.1 0.2 0.3\nKe 10 20 30.5\n");
  const Mesh mesh = loadScene(write("scene.obj",
                                    "mtllib mat.mtl\n"
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                    "usemtl wall\nf 1 2 3\n"
                                    "usemtl lamp\nf 1 3 4\n"));
  ASSERT_EQ(mesh.triangleCount(), 2);
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(mesh.reflectance[0], (Rgb{0.25, 0.5, 0.75}));
  EXPECT_EQ(mesh.emission[0], (Rgb{0, 0, 0}));
  EXPECT_EQ(mesh.reflectance[1], (Rgb{0.1, 0.2, 0.3}));
  EXPECT_EQ(mesh.emission[1], (Rgb{10, 20, 30.5}));
  EXPECT_EQ(mesh.sourceFace, (std::vector<int64_t>{0, 1}));
  EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
  expectNear(mesh.normal(0), {0, 0, 1});
}

TEST_F(SceneTest, ObjLabelsCombineMaterialAndGroup) {
  write("m.mtl", "newmtl white\nKd 0.5 0.5 0.5\nnewmtl red\nKd 0.5 0 0\n");
  const Mesh mesh = loadScene(write("labels.obj",
                                    "mtllib m.mtl\n"
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                    "f 1 2 3\n"                        // no material, no group
                                    "o Room\nusemtl white\nf 1 3 4\n"  // object only
                                    "g walls\nf 1 2 3\nf 1 2 3 4\n"    // group wins
                                    "usemtl red\nf 1 3 4\n"
                                    "g floor\nusemtl white\nf 1 2 3\n"));
  ASSERT_EQ(mesh.triangleCount(), 7);
  ASSERT_TRUE(mesh.hasLabels());
  std::vector<std::string> names;
  for (int32_t l : mesh.label) names.push_back(mesh.labelNames.at(l));
  EXPECT_EQ(names,
            (std::vector<std::string>{"no material", "white (object Room)", "white (group walls)",
                                      "white (group walls)", "white (group walls)",
                                      "red (group walls)", "white (group floor)"}));
  EXPECT_EQ(mesh.labelNames.size(), 5u);  // each distinct label once
}

TEST_F(SceneTest, ObjQuadIsTriangulatedWithItsWindingAndArea) {
  const Mesh mesh = loadScene(write("quad.obj", "v 0 0 0\nv 2 0 0\nv 2 0 3\nv 0 0 3\nf 1 4 3 2\n"));
  ASSERT_EQ(mesh.triangleCount(), 2);
  EXPECT_NEAR(mesh.totalArea(), 6, 1e-12);
  for (int64_t t = 0; t < 2; ++t) {
    expectNear(mesh.normal(t), {0, 1, 0});  // 1 4 3 2 winds counter-clockwise seen from +y
    EXPECT_EQ(mesh.sourceFace[t], 0);
  }
  EXPECT_TRUE(hasWarningWith(mesh, "without material"));
}

TEST_F(SceneTest, ObjConcavePolygonIsEarClippedInItsPlane) {
  // A U shape (area 5) whose fan from vertex 0 would fold over itself; tilted out of every
  // coordinate plane so the best-fit plane matters.
  const double u2d[8][2] = {{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const Vec3 e1 = normalize({1, 1, 0}), e2 = normalize({-1, 1, 2});
  const Vec3 origin = {5, -2, 7};
  std::string obj;
  for (const auto& p : u2d) {
    const Vec3 x = origin + p[0] * e1 + p[1] * e2;
    obj +=
        "v " + std::to_string(x.x) + " " + std::to_string(x.y) + " " + std::to_string(x.z) + "\n";
  }
  obj += "f 1 2 3 4 5 6 7 8\n";
  const Mesh mesh = loadScene(write("u.obj", obj));
  EXPECT_EQ(mesh.triangleCount(), 6);
  EXPECT_NEAR(mesh.totalArea(), 5, 1e-5);
  const Vec3 expectedNormal = normalize(cross(e1, e2));
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    expectNear(mesh.normal(t), expectedNormal, 1e-5);
}

TEST(Triangulate, ConvexPolygonGivesTheFan) {
  std::vector<Vec3> hexagon;
  for (int k = 0; k < 6; ++k) {
    hexagon.push_back({std::cos(k * std::numbers::pi / 3), std::sin(k * std::numbers::pi / 3), 0});
  }
  const detail::PolygonTriangulation split = detail::triangulatePolygon(hexagon);
  ASSERT_EQ(split.triangles.size(), 4u);
  EXPECT_TRUE(split.added.empty());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(split.triangles[i], (std::array<int, 3>{0, i + 1, i + 2}));
}

/// √3·(longest edge)² / (4·area), as the meshing report gives it.
double aspect(const Mesh& mesh, int64_t t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k);
    longest = std::max(longest, dot(e, e));
  }
  return std::sqrt(3.0) * longest / (4 * mesh.area(t));
}

/// An OBJ face of `n` corners on the circle of radius 1 about (cx, 0, cz) in the plane y = 0,
/// facing +y, and `extra` statements after it.
std::string discObj(int n, double ripple = 0, const std::string& extra = "") {
  std::string obj;
  for (int k = 0; k < n; ++k) {
    const double a = -2 * std::numbers::pi * k / n;  // from +x towards -z: faces +y
    const double r = 1 + ripple * (k % 2);
    obj.append("v ").append(std::to_string(r * std::cos(a))).append(" ");
    obj.append(std::to_string(ripple * (k % 3))).append(" ");
    obj.append(std::to_string(r * std::sin(a))).append("\n");
  }
  obj += "f";
  for (int k = 1; k <= n; ++k) obj.append(" ").append(std::to_string(k));
  return obj.append("\n").append(extra);
}

// A disc as one polygon of many corners used to become a fan of needles (aspect 2,757 for
// 5,000 corners; refined to 780,932 patches where the default aims at ~4,000). Its triangles
// are well shaped now, with points added inside only: its outline, which neighbours share, is
// kept edge for edge.
TEST_F(SceneTest, ObjPolygonOfManyCornersGetsWellShapedTriangles) {
  const int n = 400;
  const Mesh mesh =
      loadScene(write("disc.obj", discObj(n, 0, "v 0 -1 0\nv 1 -1 0\nv 0 -1 1\nf 401 402 403\n")));
  double polygonArea = 0;  // of the corners as written (6 decimals)
  for (int k = 0; k < n; ++k) {
    const Vec3 a = mesh.vertices[k], b = mesh.vertices[(k + 1) % n];
    polygonArea += 0.5 * (b.x * a.z - a.x * b.z);
  }
  double area = 0, worst = 0;
  std::map<std::pair<int64_t, int64_t>, int> edges;
  int64_t discTriangles = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] != 0) continue;
    ++discTriangles;
    area += mesh.area(t);
    worst = std::max(worst, aspect(mesh, t));
    expectNear(mesh.normal(t), {0, 1, 0}, 1e-9);
    for (int k = 0; k < 3; ++k) ++edges[{mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]}];
  }
  EXPECT_NEAR(area, polygonArea, 1e-12);
  EXPECT_LT(worst, 5) << "the ear clipping's fan reaches " << n / 4;
  EXPECT_LT(discTriangles, 4 * n);
  for (int k = 0; k < n; ++k) EXPECT_EQ((edges[{k, (k + 1) % n}]), 1) << "outline edge " << k;
  // The file's vertices keep their numbers (the triangle after the disc names 401 402 403); the
  // added points come after them, inside the disc, in its plane.
  ASSERT_GT(mesh.vertices.size(), static_cast<size_t>(n + 3));
  EXPECT_EQ(mesh.triangles.back(), (Triangle{n, n + 1, n + 2}));
  EXPECT_EQ(mesh.sourceFace.back(), 1);
  for (size_t v = n + 3; v < mesh.vertices.size(); ++v) {
    EXPECT_NEAR(mesh.vertices[v].y, 0, 1e-12);
    EXPECT_LT(std::hypot(mesh.vertices[v].x, mesh.vertices[v].z), 1);
  }
}

// A polygon of many corners out of its plane keeps the ear clipping: points added in a plane
// would lie off its surface.
TEST_F(SceneTest, ObjNonPlanarPolygonOfManyCornersIsEarClipped) {
  const Mesh mesh = loadScene(write("wavy.obj", discObj(60, 0.01)));
  EXPECT_EQ(mesh.vertices.size(), 60u);
  EXPECT_EQ(mesh.triangleCount(), 58);
}

TEST_F(SceneTest, ObjNegativeIndicesAndCornerForms) {
  const Mesh mesh = loadScene(write("forms.obj",
                                    "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                                    "f -3 -2 -1\n"
                                    "f 1/1 2/2 3/3\n"
                                    "f 1//1 2//1 3//1\n"
                                    "f 1/1/1 2/2/1 3/3/1\n"
                                    "v 0 0 1 1.0\n"  // w is ignored
                                    "f -4/-3/-1 -3 -1\n"));
  ASSERT_EQ(mesh.triangleCount(), 5);
  for (int t = 0; t < 4; ++t) EXPECT_EQ(mesh.triangles[t], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[4], (Triangle{0, 1, 3}));
  EXPECT_EQ(mesh.vertices[3], (Vec3{0, 0, 1}));
}

TEST_F(SceneTest, ObjToleratesCrlfCommentsBlanksAndTrailingSpace) {
  write("m.mtl", "# materials\r\nnewmtl a\r\nKd 0.5 0.5 0.5  \r\n\r\nKe 1 1 1\t\r\n");
  const Mesh mesh = loadScene(write("crlf.obj",
                                    "# comment\r\n\r\n   \r\nmtllib m.mtl\r\n"
                                    "o thing\r\ng group\r\ns 1\r\n"
                                    "v 0 0 0   \r\nv +1 0 0 # inline comment\r\n"
                                    "\tv 0 1e0 0\t\r\n"
                                    "usemtl a\r\nf 1 2 \\\r\n 3\r\n"));
  ASSERT_EQ(mesh.triangleCount(), 1);
  EXPECT_EQ(mesh.vertices[1], (Vec3{1, 0, 0}));
  EXPECT_EQ(mesh.emission[0], (Rgb{1, 1, 1}));
  EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
}

// Classic Mac OS files end their lines with a lone CR: such a file used to be one line,
// refused as "malformed number 'v'".
TEST_F(SceneTest, ObjWithCrOnlyLineEndsReadsAsWithLf) {
  const std::string mtl = "newmtl a\nKd 0.25 0.5 0.75\nKe 1 1 1\n";
  const std::string obj =
      "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl a\n"
      "f 1 2 3\nf 2 4 \\\n 3\n";
  auto crOnly = [](std::string text) {
    std::replace(text.begin(), text.end(), '\n', '\r');
    return text;
  };
  write("m.mtl", mtl);
  const Mesh lf = loadScene(write("lf.obj", obj));
  write("cr/m.mtl", crOnly(mtl));
  const Mesh cr = loadScene(write("cr/cr.obj", crOnly(obj)));
  ASSERT_EQ(lf.triangleCount(), 2);
  EXPECT_EQ(cr.vertices, lf.vertices);
  EXPECT_EQ(cr.triangles, lf.triangles);
  EXPECT_EQ(cr.reflectance, lf.reflectance);
  EXPECT_EQ(cr.emission, lf.emission);
  const std::string bad = write("bad.obj", crOnly("v 0 0 0\nv 1 0\n"));
  expectInputError([&] { loadScene(bad); }, {"bad.obj:2:", "three coordinates"});
}

// Names in Latin-1 (older exporters) are read, kept as \xNN in the labels with a warning, as
// docs/refusals.md says; the OBJ and MTL readers used to refuse them as "not a text file".
TEST_F(SceneTest, ObjLatin1NamesAreKeptAsEscapedBytes) {
  write("m.mtl", "newmtl Wei\xdf\nKd 0.5 0.5 0.5\n");
  const Mesh mesh = loadScene(write("l.obj",
                                    "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "g caf\xe9\nusemtl Wei\xdf\nf 1 2 3\n"));
  ASSERT_EQ(mesh.triangleCount(), 1);
  EXPECT_EQ(mesh.labelNames.at(mesh.label[0]), "Wei\\xDF (group caf\\xE9)");
  EXPECT_TRUE(hasWarningWith(mesh, "is not UTF-8 text"));
}

TEST_F(SceneTest, ObjWithByteOrderMarkAndUtf8Names) {
  write("m.mtl", "\xEF\xBB\xBFnewmtl Wand grün\nKd 0.5 0.5 0.5\n");
  const Mesh mesh =
      loadScene(write("bom.obj",
                      "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                      "mtllib m.mtl\nmtllib m.mtl\n# Größe\nusemtl Wand grün\nf 1 2 3\n"));
  EXPECT_EQ(mesh.triangleCount(), 1);
  EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
}

TEST_F(SceneTest, ObjSeveralMtllibsRelativeToTheObjFolder) {
  write("sub/a.mtl", "newmtl a\nKd 0.1 0.1 0.1\n");
  write("sub/b.mtl", "newmtl b\nKd 0.2 0.2 0.2\n");
  write("sub/more/c d.mtl", "newmtl c\nKd 0.3 0.3 0.3\nKe 2 2 2\n");
  const std::string obj = write("sub/scene.obj",
                                "mtllib a.mtl b.mtl\nmtllib more/c d.mtl\n"
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                "usemtl c\nf 1 2 3\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n");
  // Run from elsewhere: the mtllib paths must not depend on the working directory.
  const fs::path before = fs::current_path();
  fs::current_path(dir_);
  const Mesh mesh = loadScene(obj);
  fs::current_path(before);
  ASSERT_EQ(mesh.triangleCount(), 3);
  EXPECT_EQ(mesh.reflectance[0], (Rgb{0.3, 0.3, 0.3}));
  EXPECT_EQ(mesh.emission[0], (Rgb{2, 2, 2}));
  EXPECT_EQ(mesh.reflectance[1], (Rgb{0.1, 0.1, 0.1}));
  EXPECT_EQ(mesh.reflectance[2], (Rgb{0.2, 0.2, 0.2}));
}

TEST_F(SceneTest, ObjSourceFaceCountsEveryFaceStatement) {
  const Mesh mesh = loadScene(write("faces.obj",
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                                    "f 1 2 3\n"
                                    "f 1 2 5\n"  // collinear: dropped, but still face 1
                                    "f 1 2 3 4\n"
                                    "f 2 5 3 4 1\n"));
  EXPECT_EQ(mesh.sourceFace, (std::vector<int64_t>{0, 2, 2, 3, 3, 3}));
  EXPECT_TRUE(hasWarningWith(mesh, "dropped 1 degenerate"));
}

TEST_F(SceneTest, ObjIgnoredStatementsGiveOneWarningEach) {
  write("m.mtl",
        "newmtl a\nKa 1 1 1\nKd 0.5 0.5 0.5\nNs 10\nillum 2\nmap_Kd tex.png\n"
        "newmtl b\nKs 0 0 0\nKd 0.4 0.4 0.4\n");
  const Mesh mesh = loadScene(write("ign.obj",
                                    "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "l 1 2\nl 2 3\np 1\ncurv 0 1 1 2\n"
                                    "f 1 2 3\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n"));
  ASSERT_EQ(mesh.warnings.size(), 3u);
  EXPECT_TRUE(
      hasWarningWith(mesh, "ignored unsupported OBJ statements: curv (1×), l (2×), p (1×)"));
  EXPECT_TRUE(hasWarningWith(mesh, "Ka, Ks, Ns, illum, map_Kd"));
  EXPECT_TRUE(hasWarningWith(mesh, "1 face(s) without material"));
  EXPECT_EQ(mesh.reflectance[0], detail::kDefaultReflectance);
  EXPECT_EQ(mesh.emission[0], (Rgb{0, 0, 0}));
}

TEST_F(SceneTest, ObjMaterialWithoutKdIsWarnedAbout) {
  write("m.mtl", "newmtl glow\nKe 3 3 3\n");
  const Mesh mesh = loadScene(
      write("nokd.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glow\nf 1 2 3\n"));
  EXPECT_EQ(mesh.reflectance[0], detail::kDefaultReflectance);
  EXPECT_EQ(mesh.emission[0], (Rgb{3, 3, 3}));
  EXPECT_TRUE(hasWarningWith(mesh, "m.mtl:1: material 'glow' has no Kd"));
}

TEST_F(SceneTest, ObjErrorsNameFileAndLine) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  struct Case {
    std::string obj;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"v 0 0 0\nv 1 x 0\n", {"bad.obj:2:", "malformed number 'x'"}},
      {"v 0 0 0\nv 1 1.5.3 0\n", {"bad.obj:2:", "malformed number"}},
      {"v 0 0\n", {"bad.obj:1:", "three coordinates"}},
      {tri + "f 0 1 2\n", {"bad.obj:4:", "face index 0"}},
      {tri + "f 1 2 4\n", {"bad.obj:4:", "face index 4 out of range"}},
      {tri + "f -4 1 2\n", {"bad.obj:4:", "face index -4 out of range"}},
      {tri + "\n# x\nf 1 2\n", {"bad.obj:6:", "face with 2 vertices"}},
      {tri + "f 1/ 2 3\n", {"bad.obj:4:", "malformed face corner '1/'"}},
      {tri + "f 1/1/1/1 2 3\n", {"bad.obj:4:", "malformed face corner"}},
      {tri + "f 1 a 3\n", {"bad.obj:4:", "malformed face corner 'a'"}},
      {tri + "v 1 1 0\nf 1 2 4 4\n", {"bad.obj:5:", "names vertex 4 twice"}},
      {tri + "v 1 1 0\nf 1 2 -1 3 4\n", {"bad.obj:5:", "names vertex 4 twice"}},
      {tri + "usemtl nothing\nf 1 2 3\n", {"bad.obj:4:", "unknown material 'nothing'"}},
      {"mtllib missing.mtl\n" + tri, {"bad.obj:1:", "missing.mtl"}},
      {"v nan 0 0\n", {"bad.obj:1:", "not finite"}},
      {"v 0 inf 0\n", {"bad.obj:1:", "not finite"}},
      {"v 0 0 1e31\n", {"bad.obj:1:", "exceeds 1e30"}},
      {"v 0 0 1e999\n", {"bad.obj:1:", "out of range"}},
      {tri + "f 1 2 3\nv 0 0\0 1\n"s, {"bad.obj:5:", "not a text file"}},
      {"v 0 0 0\n", {"bad.obj", "scene has no triangles"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.obj);
    const std::string path = write("bad.obj", c.obj);
    expectInputError([&] { loadScene(path); }, c.expected);
  }
}

// A face naming few vertices many times used to be ear-clipped (quadratic in its corners: 75 s
// for 60,000) into coincident copies of one triangle.
TEST_F(SceneTest, ObjLongFaceNamingAVertexTwiceIsRefusedAtOnce) {
  std::string face = "f";
  for (int k = 0; k < 60000; ++k) face.append(" ").append(std::to_string(1 + k % 3));
  const std::string path =
      write("long.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n").append(face).append("\n"));
  expectInputError([&] { loadScene(path); }, {"long.obj:4:", "names vertex 1 twice"});
}

TEST_F(SceneTest, ObjUsemtlUnknownNamesTheUsemtlLine) {
  write("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\n");
  const std::string path =
      write("u.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib m.mtl\nusemtl a\nf 1 2 3\nusemtl b\n");
  expectInputError([&] { loadScene(path); }, {"u.obj:7:", "unknown material 'b'", "m.mtl"});
}

TEST_F(SceneTest, MtlErrorsNameTheMtlFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"newmtl a\n\nKd 1.2 0.5 0.5\n", "within [0, 1]"},
      {"newmtl a\n\nKd 0.5 -0.1 0.5\n", "within [0, 1]"},
      {"newmtl a\n\nKd 0.5 nan 0.5\n", "non-finite"},
      {"newmtl a\n\nKd 0.5 0.5\n", "three numbers"},
      {"newmtl a\n\nKd 0.5 0.5 zero\n", "malformed number 'zero'"},
      {"newmtl a\n\nKe -1 0 0\n", "negative emission"},
      {"newmtl a\n\nKe inf 0 0\n", "non-finite"},
      {"# no newmtl\n\nKd 0.5 0.5 0.5\n", "before any newmtl"},
      {"newmtl a\n\nKd spectral file.spd\n", "not supported"},
      {"newmtl a\n\nKd 0.5 0.5 0.5\0\n"s, "not a text file"},
  };
  for (const auto& [mtl, problem] : cases) {
    SCOPED_TRACE(mtl);
    write("m.mtl", mtl);
    const std::string path =
        write("s.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    expectInputError([&] { loadScene(path); }, {"m.mtl:3:", problem});
  }
}

TEST_F(SceneTest, MtlSingleValueIsGrey) {
  write("m.mtl", "newmtl a\nKd 0.3\nKe 2\n");
  const Mesh mesh =
      loadScene(write("s.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"));
  EXPECT_EQ(mesh.reflectance[0], (Rgb{0.3, 0.3, 0.3}));
  EXPECT_EQ(mesh.emission[0], (Rgb{2, 2, 2}));
}

TEST_F(SceneTest, UnreadableFilesAreInputErrorsNamingThem) {
  const std::string missing = (dir_ / "nowhere.obj").string();
  expectInputError([&] { loadScene(missing); }, {"nowhere.obj", "cannot read"});
  expectInputError([&] { loadScene((dir_ / "nowhere.ply").string()); }, {"nowhere.ply"});
  const std::string xyz = write("scene.xyz", "x\n");
  expectInputError([&] { loadScene(xyz); }, {"scene.xyz", "unknown scene format"});
  const std::string folder = (dir_ / "folder.obj").string();
  fs::create_directories(folder);
  expectInputError([&] { loadScene(folder); }, {"folder.obj"});
}

TEST_F(SceneTest, DegenerateTrianglesAreDroppedWithOneWarning) {
  const Mesh mesh = loadScene(write("deg.obj",
                                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 0.5 0 1e-13\n"
                                    "f 1 2 3\nf 1 2 4\nf 1 1 3\nf 1 5 2\n"));
  ASSERT_EQ(mesh.triangleCount(), 1);
  EXPECT_EQ(mesh.sourceFace[0], 0);
  EXPECT_EQ(
      std::count_if(mesh.warnings.begin(), mesh.warnings.end(),
                    [](const std::string& w) { return w.find("degenerate") != std::string::npos; }),
      1);
  EXPECT_TRUE(hasWarningWith(mesh, "deg.obj: dropped 3 degenerate"));
  expectInputError([&] { loadScene(write("all.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")); },
                   {"all.obj", "scene has no triangles"});
}

TEST_F(SceneTest, WrittenObjReadsBackIdentically) {
  for (const std::string spec :
       {"builtin:cornell", "builtin:box?rho=0.3&e=0.7&size=2.5", "builtin:plates",
        "builtin:sphere?level=1", "builtin:cornell?light=0.1", "builtin:rooms?patches=1000",
        "builtin:plates?angle=90&width=2"}) {
    SCOPED_TRACE(spec);
    const Mesh original = loadScene(spec);
    const std::string path = (dir_ / "out.obj").string();
    writeSceneObj(original, path);
    EXPECT_TRUE(fs::exists(dir_ / "out.mtl"));
    const Mesh back = loadScene(path);
    EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
    EXPECT_EQ(back.vertices, original.vertices);
    EXPECT_EQ(back.triangles, original.triangles);
    EXPECT_EQ(back.reflectance, original.reflectance);
    EXPECT_EQ(back.emission, original.emission);
    std::vector<int64_t> iota(original.triangles.size());
    std::iota(iota.begin(), iota.end(), 0);
    EXPECT_EQ(back.sourceFace, iota);
  }
  // Nothing but the two files is left in the folder (no temporaries).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2);
}

TEST_F(SceneTest, WriterUsesOneMaterialPerDistinctPair) {
  const Mesh cornell = loadScene("builtin:cornell");
  const std::string path = (dir_ / "c.obj").string();
  writeSceneObj(cornell, path);
  std::ifstream mtl(dir_ / "c.mtl");
  int count = 0;
  for (std::string line; std::getline(mtl, line);) count += line.starts_with("newmtl ");
  EXPECT_EQ(count, 4);  // white, light, green, red
}

TEST_F(SceneTest, WriterFailureIsAnErrorAndLeavesNothing) {
  const Mesh box = loadScene("builtin:box");
  const std::string path = (dir_ / "no" / "such" / "folder.obj").string();
  try {
    writeSceneObj(box, path);
    ADD_FAILURE() << "no Error thrown";
  } catch (const InputError&) {
    ADD_FAILURE() << "a write failure is not bad input";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 0);
}

}  // namespace
}  // namespace radiosity
