// Scene input: the OBJ/MTL reader, PLY/OFF through OpenMesh, validation, the built-in scenes and
// the OBJ writer. Every error must name the file and line the user has to fix.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>
#include <set>

#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using namespace std::string_literals;  // "...\0..."s keeps the NUL bytes

/// A fresh folder per test, removed afterwards.
class SceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() /
           ("io_scene_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Writes `content` byte for byte to `name` inside the test folder; returns the full path.
  std::string write(const std::string& name, const std::string& content) {
    const fs::path path = dir_ / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << content;
    return path.string();
  }

  fs::path dir_;
};

/// Runs `f`, expects an InputError (exit code 3) whose message contains every one of `parts`.
void expectInputError(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
    for (const auto& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
    }
  }
}

bool hasWarningWith(const Mesh& mesh, const std::string& text) {
  for (const auto& w : mesh.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

void expectNear(Vec3 a, Vec3 b, double tolerance = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

/// Every directed edge appears once and its reverse once: closed and consistently oriented.
bool closedAndOriented(const Mesh& mesh) {
  std::map<std::pair<int64_t, int64_t>, int> directed;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != 1) return false;
  }
  return true;
}

/// Signed volume enclosed (divergence theorem): negative when the normals point inward.
double signedVolume(const Mesh& mesh) {
  double v = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    v += dot(mesh.corner(t, 0), cross(mesh.corner(t, 1), mesh.corner(t, 2))) / 6;
  }
  return v;
}

// ---------------------------------------------------------------------------------------------
// OBJ + MTL

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
  const auto triangles = detail::triangulatePolygon(hexagon);
  ASSERT_EQ(triangles.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(triangles[i], (std::array<int, 3>{0, i + 1, i + 2}));
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
      {tri + "usemtl nothing\nf 1 2 3\n", {"bad.obj:4:", "unknown material 'nothing'"}},
      {"mtllib missing.mtl\n" + tri, {"bad.obj:1:", "missing.mtl"}},
      {"v nan 0 0\n", {"bad.obj:1:", "not finite"}},
      {"v 0 inf 0\n", {"bad.obj:1:", "not finite"}},
      {"v 0 0 1e31\n", {"bad.obj:1:", "exceeds 1e30"}},
      {"v 0 0 1e999\n", {"bad.obj:1:", "out of range"}},
      {tri + "f 1 2 3\nv 0 0\0 1\n"s, {"bad.obj:5:", "not a text file"}},
      {tri + "g caf\xe9\n", {"bad.obj:4:", "not a text file"}},
      {"v 0 0 0\n", {"bad.obj", "scene has no triangles"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.obj);
    const std::string path = write("bad.obj", c.obj);
    expectInputError([&] { loadScene(path); }, c.expected);
  }
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
  const std::string stl = write("scene.stl", "solid x\n");
  expectInputError([&] { loadScene(stl); }, {"scene.stl", "unknown scene format"});
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

// ---------------------------------------------------------------------------------------------
// Validation of meshes from any source

Mesh oneTriangle() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  mesh.sourceFace = {0};
  mesh.reflectance = {{0.5, 0.5, 0.5}};
  mesh.emission = {{0, 0, 0}};
  return mesh;
}

TEST(Validation, RefusesWhatLaterStagesCannotUse) {
  auto expectRefused = [](const std::function<void(Mesh&)>& spoil, const std::string& problem) {
    Mesh mesh = oneTriangle();
    spoil(mesh);
    expectInputError([&] { detail::validateScene(mesh, "src"); }, {"src", problem});
  };
  expectRefused([](Mesh& m) { m.reflectance[0][1] = 1.0000001; }, "reflectance");
  expectRefused([](Mesh& m) { m.reflectance[0][2] = -0.1; }, "reflectance");
  expectRefused([](Mesh& m) { m.reflectance[0][0] = NAN; }, "reflectance");
  expectRefused([](Mesh& m) { m.emission[0][0] = -1; }, "emission");
  expectRefused([](Mesh& m) { m.emission[0][2] = INFINITY; }, "emission");
  expectRefused([](Mesh& m) { m.vertices[1].x = NAN; }, "vertex 2");
  expectRefused([](Mesh& m) { m.vertices[2].y = -INFINITY; }, "vertex 3");
  expectRefused([](Mesh& m) { m.vertices[0].z = 1e31; }, "vertex 1");
  expectRefused([](Mesh& m) { m.triangles[0][2] = 3; }, "vertex index 3");
  expectRefused([](Mesh& m) { m.triangles[0][0] = -1; }, "vertex index -1");
  Mesh fine = oneTriangle();
  fine.vertices = {{-1e30, 0, 0}, {1e30, 0, 0}, {0, 1e30, 0}};  // the largest magnitude allowed
  fine.reflectance[0] = {0, 1, 0.5};
  EXPECT_NO_THROW(detail::validateScene(fine, "src"));
}

TEST(Validation, DegeneracyIsRelativeToTheSceneSize) {
  Mesh big = oneTriangle();
  for (Vec3& v : big.vertices) v = 1e6 * v;  // area 5e11, not degenerate at any scale
  big.vertices.push_back({1e6, 1e6, 0});
  big.vertices.push_back({1e6 + 1e-4, 1e6, 0});
  big.vertices.push_back({1e6, 1e6 + 1e-4, 0});  // area 5e-9 < 1e-12 × diag² = 2
  big.triangles.push_back({3, 4, 5});
  big.sourceFace.push_back(1);
  big.reflectance.push_back({0, 0, 0});
  big.emission.push_back({0, 0, 0});
  detail::validateScene(big, "big");
  EXPECT_EQ(big.triangleCount(), 1);
  EXPECT_EQ(big.warnings.size(), 1u);

  Mesh tiny = oneTriangle();
  for (Vec3& v : tiny.vertices) v = 1e-9 * v;  // tiny, but the whole scene: kept
  detail::validateScene(tiny, "tiny");
  EXPECT_EQ(tiny.triangleCount(), 1);
  EXPECT_TRUE(tiny.warnings.empty());
}

// ---------------------------------------------------------------------------------------------
// PLY and OFF through OpenMesh

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

// ---------------------------------------------------------------------------------------------
// Built-in scenes

TEST(Builtin, NamesAreListed) {
  const auto names = builtinSceneNames();
  for (const char* name : {"cornell", "box", "plates", "sphere", "rooms"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
}

TEST(Builtin, CornellBoxGeometryMaterialsAndOrientation) {
  const Mesh mesh = loadScene("builtin:cornell");
  EXPECT_TRUE(mesh.warnings.empty());
  // The floor comes first, cut around the blocks' footprints into convex pieces (faces
  // 0 .. floorFaces − 1); then 9 ceiling cells, 3 walls, 2 × 5 block faces.
  int64_t floorFaces = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.labelNames.at(mesh.label[t]) == "floor")
      floorFaces = std::max(floorFaces, mesh.sourceFace[t] + 1);
  }
  EXPECT_EQ(floorFaces, 17);  // 9 slabs between the corners' z; 1, 2 or 3 pieces each
  EXPECT_EQ(mesh.sourceFace.back(), floorFaces + 21);
  const int64_t f0 = floorFaces - 1;  // face numbers below are those of a one-piece floor + f0
  // No floor under the blocks: the floor's area is the room's less the two footprints.
  double floorArea = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    if (mesh.sourceFace[t] < floorFaces) floorArea += mesh.area(t);
  auto shoelace = [](const std::vector<std::array<double, 2>>& p) {
    double twice = 0;
    for (size_t k = 0; k < p.size(); ++k) {
      const auto& a = p[k];
      const auto& b = p[(k + 1) % p.size()];
      twice += a[0] * b[1] - b[0] * a[1];
    }
    return std::abs(twice) / 2;
  };
  const double footprints = shoelace({{130, 65}, {290, 114}, {240, 272}, {82, 225}}) +
                            shoelace({{423, 247}, {472, 406}, {314, 456}, {265, 296}});
  EXPECT_NEAR(floorArea, 0.5 * (552.8 + 549.6) * 559.2 - footprints, 1e-6 * floorArea);
  // Floor ≈ ceiling ≈ walls ≈ 0.3 m², blocks ≈ 0.14 and 0.25 m²: about 1.9 m² in mm².
  EXPECT_GT(mesh.totalArea(), 1.8e6);
  EXPECT_LT(mesh.totalArea(), 2.0e6);

  const Rgb light = {std::numbers::pi * 17, std::numbers::pi * 12, std::numbers::pi * 4};
  double lightArea = 0;
  int emitting = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const int64_t face = mesh.sourceFace[t];
    const Vec3 n = mesh.normal(t), c = mesh.centroid(t);
    if (mesh.emission[t][0] > 0) {
      ++emitting;
      lightArea += mesh.area(t);
      EXPECT_EQ(face, 5 + f0);
      EXPECT_EQ(mesh.emission[t], light);
      expectNear(n, {0, -1, 0});
    }
    if (face <= f0) {
      expectNear(n, {0, 1, 0});
    } else if (face >= 1 + f0 && face <= 9 + f0) {
      expectNear(n, {0, -1, 0});
    }
    if (face <= 12 + f0) {
      EXPECT_GT(dot(n, Vec3{278, 274, 280} - c), 0) << "room face " << face << " faces outward";
    } else {
      const Vec3 blockCentre =
          face <= 17 + f0 ? Vec3{185.5, 82.5, 169} : Vec3{368.5, 165, 351.25};
      EXPECT_GT(dot(n, c - blockCentre), 0) << "block face " << face << " faces inward";
    }
    if (face == 13 + f0 || face == 18 + f0) expectNear(n, {0, 1, 0});
  }
  EXPECT_EQ(emitting, 2);
  EXPECT_NEAR(lightArea, 130.0 * 105.0, 1e-9);
  // Red on the x ≈ 556 wall, green on x = 0.
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] == 11 + f0) {
      EXPECT_EQ(mesh.reflectance[t], (Rgb{0.14, 0.45, 0.091}));
    }
    if (mesh.sourceFace[t] == 12 + f0) {
      EXPECT_EQ(mesh.reflectance[t], (Rgb{0.63, 0.065, 0.05}));
    }
  }
  // The ceiling cells and the light form one conforming grid: 16 shared vertices.
  std::set<int64_t> ceiling;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] >= 1 + f0 && mesh.sourceFace[t] <= 9 + f0) {
      ceiling.insert(mesh.triangles[t].begin(), mesh.triangles[t].end());
    }
  }
  EXPECT_EQ(ceiling.size(), 16u);

  const Mesh brighter = loadScene("builtin:cornell?light=2.5");
  for (int64_t t = 0; t < brighter.triangleCount(); ++t) {
    if (brighter.sourceFace[t] == 5 + f0) {
      EXPECT_NEAR(brighter.emission[t][0], 2.5 * light[0], 1e-12);
    }
  }
}

TEST(Builtin, ScenesLabelTheirSurfaces) {
  const Mesh cornell = loadScene("builtin:cornell");
  ASSERT_TRUE(cornell.hasLabels());
  std::map<std::string, int> triangles;
  for (size_t t = 0; t < cornell.label.size(); ++t) {
    const std::string& name = cornell.labelNames.at(cornell.label[t]);
    ++triangles[name];
    EXPECT_EQ(cornell.emission[t][0] > 0, name == "light") << name;
  }
  EXPECT_EQ(triangles, (std::map<std::string, int>{{"floor", 34},
                                                   {"ceiling", 16},
                                                   {"light", 2},
                                                   {"back wall", 2},
                                                   {"red wall", 2},
                                                   {"green wall", 2},
                                                   {"short block", 10},
                                                   {"tall block", 10}}));
  for (const char* spec : {"builtin:box", "builtin:plates", "builtin:sphere?level=0"}) {
    const Mesh mesh = loadScene(spec);
    EXPECT_TRUE(mesh.hasLabels()) << spec;
  }
  EXPECT_EQ(loadScene("builtin:box").labelNames.size(), 6u);
}

TEST(Builtin, BoxIsClosedWithInwardNormals) {
  const Mesh mesh = loadScene("builtin:box?rho=0.8&e=2&size=3");
  EXPECT_EQ(mesh.triangleCount(), 12);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_TRUE(closedAndOriented(mesh));
  EXPECT_NEAR(signedVolume(mesh), -27, 1e-9);  // negative: normals point inward
  EXPECT_NEAR(mesh.totalArea(), 54, 1e-9);
  for (int64_t t = 0; t < 12; ++t) {
    EXPECT_GT(dot(mesh.normal(t), Vec3{1.5, 1.5, 1.5} - mesh.centroid(t)), 0);
    EXPECT_EQ(mesh.reflectance[t], (Rgb{0.8, 0.8, 0.8}));
    EXPECT_EQ(mesh.emission[t], (Rgb{2, 2, 2}));
    EXPECT_EQ(mesh.sourceFace[t], t / 2);
  }
  const Mesh defaults = loadScene("builtin:box");
  EXPECT_EQ(defaults.reflectance[0], (Rgb{0.5, 0.5, 0.5}));
  EXPECT_EQ(defaults.emission[0], (Rgb{1, 1, 1}));
  EXPECT_NEAR(defaults.totalArea(), 6, 1e-12);
}

TEST(Builtin, PlatesFaceEachOtherWithTheKnownViewFactor) {
  const Mesh mesh = loadScene("builtin:plates?e=3&rho=0.25");
  ASSERT_EQ(mesh.triangleCount(), 4);
  for (int64_t t = 0; t < 4; ++t) {
    const bool emitter = mesh.sourceFace[t] == 0;
    expectNear(mesh.normal(t), {0, 0, emitter ? 1.0 : -1.0});
    EXPECT_EQ(mesh.centroid(t).z, emitter ? 0 : 1);
    EXPECT_EQ(mesh.emission[t], (emitter ? Rgb{3, 3, 3} : Rgb{0, 0, 0}));
    EXPECT_EQ(mesh.reflectance[t], (emitter ? Rgb{0, 0, 0} : Rgb{0.25, 0.25, 0.25}));
  }
  EXPECT_NEAR(mesh.totalArea(), 2, 1e-12);
  // Midpoint quadrature of F = ∫∫ cosθ₁ cosθ₂ / (π r²) over the two unit squares.
  const int n = 20;
  double f = 0;
  for (int i = 0; i < n * n; ++i) {
    for (int j = 0; j < n * n; ++j) {
      const double dx = ((i % n) - (j % n)) / double(n), dy = ((i / n) - (j / n)) / double(n);
      const double r2 = dx * dx + dy * dy + 1;
      f += 1 / (std::numbers::pi * r2 * r2);
    }
  }
  f /= double(n) * n * n * n;
  EXPECT_NEAR(f, 0.19982, 1e-3);

  const Mesh far = loadScene("builtin:plates?distance=2.5&rho_emitter=0.5");
  EXPECT_EQ(far.centroid(3).z, 2.5);
  EXPECT_EQ(far.reflectance[0], (Rgb{0.5, 0.5, 0.5}));
}

TEST(Builtin, PlatesTakeSizesAndAPerpendicularVariant) {
  const Mesh sized = loadScene("builtin:plates?width=2&height=0.5&distance=3");
  EXPECT_NEAR(sized.totalArea(), 2, 1e-12);
  EXPECT_EQ(sized.centroid(3).z, 3);
  const Mesh bent = loadScene("builtin:plates?angle=90&width=2&height=0.5");
  ASSERT_EQ(bent.triangleCount(), 4);
  EXPECT_EQ(bent.vertices.size(), 6u);  // the common edge is shared
  for (int64_t t = 0; t < 4; ++t) {
    const bool emitter = bent.sourceFace[t] == 0;
    expectNear(bent.normal(t), emitter ? Vec3{0, 0, 1} : Vec3{0, 1, 0});
    EXPECT_NEAR(bent.area(t), 0.5, 1e-12);
    if (!emitter) {
      EXPECT_EQ(bent.centroid(t).y, 0);
      EXPECT_GT(bent.centroid(t).z, 0);
    }
  }
  expectInputError([] { loadScene("builtin:plates?angle=45"); }, {"'angle' must be 0 or 90"});
  expectInputError([] { loadScene("builtin:plates?angle=90&distance=2"); },
                   {"'distance'", "angle=0"});
  expectInputError([] { loadScene("builtin:plates?width=0"); }, {"'width'", "out of range"});
}

/// The triangles of `mesh` labelled `name`.
std::vector<int64_t> labelled(const Mesh& mesh, const std::string& name) {
  std::vector<int64_t> out;
  const auto it = std::find(mesh.labelNames.begin(), mesh.labelNames.end(), name);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (it != mesh.labelNames.end() && mesh.label[t] == it - mesh.labelNames.begin()) {
      out.push_back(t);
    }
  }
  return out;
}

TEST(Builtin, RoomsHaveTheRequestedSizeAndFaceTheirLitSides) {
  for (int64_t target : {1000, 10000, 100000}) {
    SCOPED_TRACE(target);
    const Mesh mesh = loadScene("builtin:rooms?patches=" + std::to_string(target));
    EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
    EXPECT_GE(mesh.triangleCount(), target - target / 5);
    EXPECT_LE(mesh.triangleCount(), target + target / 5);
    ASSERT_TRUE(mesh.hasLabels());

    // Every room has a light in its ceiling, facing down.
    const auto lights = labelled(mesh, "light");
    ASSERT_FALSE(lights.empty());
    for (int64_t t : lights) {
      EXPECT_GT(mesh.emission[t][0], 0);
      expectNear(mesh.normal(t), {0, -1, 0});
    }
    for (int64_t t : labelled(mesh, "floor")) expectNear(mesh.normal(t), {0, 1, 0});
    for (int64_t t : labelled(mesh, "ceiling")) expectNear(mesh.normal(t), {0, -1, 0});
    // Walls face the centre of their room (rooms are 4 m squares from the origin).
    for (int64_t t : labelled(mesh, "wall")) {
      const Vec3 c = mesh.centroid(t);
      const Vec3 centre = {(std::floor(c.x / 4) + 0.5) * 4, c.y, (std::floor(c.z / 4) + 0.5) * 4};
      EXPECT_GT(dot(mesh.normal(t), centre - c), 0) << "wall triangle " << t;
    }
    // Furniture faces out, away from the centre of its box: 5 consecutive source faces, the
    // top first.
    for (const char* piece : {"table", "shelf"}) {
      const auto triangles = labelled(mesh, piece);
      ASSERT_FALSE(triangles.empty()) << piece;
      std::map<int64_t, std::pair<Vec3, Vec3>> boxes;  // first source face → bounds
      int64_t first = -1;
      std::map<int64_t, int64_t> boxOf;
      for (int64_t t : triangles) {
        const int64_t f = mesh.sourceFace[t];
        if (first < 0 || f >= first + 5) first = f;
        boxOf[t] = first;
        auto& [lo, hi] =
            boxes.try_emplace(first, Vec3{1e9, 1e9, 1e9}, Vec3{-1e9, -1e9, -1e9}).first->second;
        for (int k = 0; k < 3; ++k) {
          for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], mesh.corner(t, k)[a]);
            hi[a] = std::max(hi[a], mesh.corner(t, k)[a]);
          }
        }
      }
      for (int64_t t : triangles) {
        const auto& [lo, hi] = boxes[boxOf[t]];
        EXPECT_GT(dot(mesh.normal(t), mesh.centroid(t) - 0.5 * (lo + hi)), 0) << piece << " " << t;
      }
    }
    // Closed apart from the furniture's open bottoms: every edge is used by two triangles in
    // opposite directions, except rims lying on the floor.
    std::map<std::pair<int64_t, int64_t>, int> directed;
    for (const Triangle& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
      ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " repeated";
      if (!directed.contains({edge.second, edge.first})) {
        ASSERT_EQ(mesh.vertices[edge.first].y, 0);
        ASSERT_EQ(mesh.vertices[edge.second].y, 0);
      }
    }
  }
  // About one room per 2000 triangles in a near-square plan (one light each); the same scene
  // for the same seed, another for another.
  auto rooms = [](const Mesh& mesh) {
    std::set<int64_t> faces;
    for (int64_t t : labelled(mesh, "light")) faces.insert(mesh.sourceFace[t]);
    return faces.size();
  };
  EXPECT_EQ(rooms(loadScene("builtin:rooms?patches=1000")), 1u);
  const Mesh a = loadScene("builtin:rooms?patches=20000&seed=3");
  EXPECT_EQ(rooms(a), 9u);
  EXPECT_EQ(a.vertices, loadScene("builtin:rooms?patches=20000&seed=3").vertices);
  EXPECT_NE(a.vertices, loadScene("builtin:rooms?patches=20000&seed=4").vertices);
  expectInputError([] { loadScene("builtin:rooms?patches=999"); }, {"'patches'", "out of range"});
  expectInputError([] { loadScene("builtin:rooms?patches=10000001"); }, {"out of range"});
  expectInputError([] { loadScene("builtin:rooms?patches=1500.5"); }, {"integer"});
}

TEST(Builtin, SphereIsAClosedInwardEnclosure) {
  const Mesh mesh = loadScene("builtin:sphere?level=3&radius=2&rho=0.999");
  EXPECT_EQ(mesh.triangleCount(), 20 * 64);
  EXPECT_TRUE(closedAndOriented(mesh));
  EXPECT_LT(signedVolume(mesh), 0);
  EXPECT_NEAR(-signedVolume(mesh), 4.0 / 3.0 * std::numbers::pi * 8, 0.7);
  EXPECT_EQ(mesh.reflectance[0], (Rgb{0.999, 0.999, 0.999}));
}

TEST(Builtin, SphereCapLimitsEmissionToTheTopCap) {
  // A spherical cap z > c·r has the area fraction (1 − c)/2: a quarter for c = 0.5, up to
  // faceting (which triangles' centroids fall above the plane) at level 3.
  const Mesh capped = loadScene("builtin:sphere?level=3&radius=2&e=3&cap=0.5");
  double emitting = 0;
  for (int64_t t = 0; t < capped.triangleCount(); ++t) {
    const bool above = capped.centroid(t).z > 0.5 * 2;
    EXPECT_EQ(capped.emission[t], (above ? Rgb{3, 3, 3} : Rgb{0, 0, 0})) << t;
    if (above) emitting += capped.area(t);
  }
  EXPECT_NEAR(emitting / capped.totalArea(), 0.25, 0.005);
  EXPECT_GT(emitting, 0);

  // cap = 1: nothing emits; cap = −1 (the default): the old scene, every triangle emitting.
  const Mesh none = loadScene("builtin:sphere?level=2&cap=1");
  for (const Rgb& e : none.emission) EXPECT_EQ(e, (Rgb{0, 0, 0}));
  const Mesh all = loadScene("builtin:sphere?level=3&radius=2&e=3&cap=-1");
  const Mesh old = loadScene("builtin:sphere?level=3&radius=2&e=3");
  EXPECT_EQ(all.vertices, old.vertices);
  EXPECT_EQ(all.triangles, old.triangles);
  EXPECT_EQ(all.emission, old.emission);
  EXPECT_EQ(all.reflectance, old.reflectance);
  for (const Rgb& e : all.emission) EXPECT_EQ(e, (Rgb{3, 3, 3}));
  // The geometry does not depend on the cap.
  EXPECT_EQ(capped.vertices, old.vertices);
  EXPECT_EQ(capped.triangles, old.triangles);

  expectInputError([] { loadScene("builtin:sphere?cap=1.5"); }, {"'cap'", "out of range"});
  expectInputError([] { loadScene("builtin:sphere?cap=-2"); }, {"'cap'", "out of range"});
}

TEST(Builtin, BadSpecsAreInputErrors) {
  expectInputError([] { loadScene("builtin:box?foo=1"); },
                   {"builtin:box?foo=1: unknown parameter 'foo' (known: rho, e, size)"});
  expectInputError([] { loadScene("builtin:nothing"); },
                   {"builtin:nothing", "unknown built-in scene 'nothing'", "cornell"});
  expectInputError([] { loadScene("builtin:box?rho=abc"); }, {"'rho'", "not a finite number"});
  expectInputError([] { loadScene("builtin:box?rho=1.5"); }, {"'rho'", "out of range"});
  expectInputError([] { loadScene("builtin:box?e=-1"); }, {"'e'", "out of range"});
  expectInputError([] { loadScene("builtin:box?size=0"); }, {"'size'", "out of range"});
  expectInputError([] { loadScene("builtin:box?rho=nan"); }, {"'rho'"});
  expectInputError([] { loadScene("builtin:box?rho"); }, {"malformed parameter 'rho'"});
  expectInputError([] { loadScene("builtin:box?rho=0.1&rho=0.2"); }, {"given twice"});
  expectInputError([] { loadScene("builtin:cornell?rho=0.1"); }, {"(known: light, scale)"});
  expectInputError([] { loadScene("builtin:sphere?level=1.5"); }, {"integer"});
  expectInputError([] { loadScene("builtin:"); }, {"unknown built-in scene ''"});
}

// ---------------------------------------------------------------------------------------------
// OBJ writer

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

// ---------------------------------------------------------------------------------------------
// PLY and OFF bodies are walked before OpenMesh reads them: nothing silently wrong.

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
  const Mesh mesh = loadScene(write(
      "d.ply", header + "0.1 0 0\n1.0000000001 0 1e-40\n0 1 0.30000000000000004\n3 0 1 2\n"));
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

// A triangle that names a vertex twice has no area: dropped with a warning, as in OBJ, and the
// faces after it keep their own numbers and materials. A larger face that repeats a corner is
// refused: its outline is ambiguous.
TEST_F(SceneTest, PlyAndOffFacesRepeatingACorner) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 3\nproperty list uchar int vertex_indices\n"
      "property float emit_red\nproperty float emit_green\nproperty float emit_blue\n"
      "end_header\n";
  const Mesh mesh = loadScene(write(
      "r.ply", header + kVertices + "3 0 1 1 5 5 5\n3 0 1 2 7 7 7\n3 0 2 3 9 9 9\n"));
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
  expectInputError([&] { loadScene(write("qb.ply", binaryPly({{0, 1, 0, 2}}, 1))); },
                   {"qb.ply: face 0 (counting from 0)", "vertex 0 twice"});
  const Mesh off = loadScene(write("r.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                            "3 3 3 1\n4 0 1 2 3\n"));
  EXPECT_EQ(off.triangleCount(), 2);
  EXPECT_EQ(off.sourceFace, (std::vector<int64_t>{1, 1}));
  EXPECT_TRUE(hasWarningWith(off, "r.off:7: dropped 1 face(s) that name a vertex twice"));
  expectInputError([&] { loadScene(write("q.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                                  "4 0 1 3 3\n")); },
                   {"q.off:7", "face 0 (counting from 0)", "vertex 3 twice"});
}

// A plain OFF vertex line holds x y z and nothing else (colours need COFF, normals NOFF).
TEST_F(SceneTest, PlainOffVertexLinesHoldThreeValues) {
  expectInputError([&] { loadScene(write("x.off", "OFF\n3 1 0\n0 0 0\n1 0 0 0.5\n0 1 0\n"
                                                  "3 0 1 2\n")); },
                   {"x.off:4", "vertex 1 (counting from 0) has 4 values", "COFF"});
  expectInputError([&] { loadScene(write("y.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n")); },
                   {"y.off:4", "vertex 1 (counting from 0) has 2 values"});
}

}  // namespace
}  // namespace radiosity
