// Reliability suite (issue 25): geometry. Degeneracy judged per triangle, scenes at any scale,
// coordinates the tracing frame cannot hold refused, sizes a file claims bounded by the file.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "end_to_end_fixture.h"
#include "io/store/result.h"
#include "obj_room.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::ProgramRun;

// The unit cube (normals in, 12 triangles) as OBJ text from vertex `first` on, each wall of
// material `wall`, scaled by `scale`; then, if `light`, a 0.2-wide light of material "light"
// under the ceiling, facing down (2 triangles).
std::string room(double scale, int first, const std::string& wall, bool light) {
  std::ostringstream obj;
  obj.precision(17);
  for (int i = 0; i < 8; ++i)
    obj << "v " << scale * (i & 1) << ' ' << scale * ((i >> 1) & 1) << ' ' << scale * ((i >> 2) & 1)
        << '\n';
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  obj << "usemtl " << wall << '\n';
  for (const auto& f : faces) {
    obj << "f " << first + f[0] << ' ' << first + f[1] << ' ' << first + f[2] << '\n';
    obj << "f " << first + f[0] << ' ' << first + f[2] << ' ' << first + f[3] << '\n';
  }
  if (light) {
    for (auto [x, y] : {std::pair{0.4, 0.4}, {0.6, 0.4}, {0.6, 0.6}, {0.4, 0.6}})
      obj << "v " << scale * x << ' ' << scale * y << ' ' << scale * 0.99 << '\n';
    const int l = first + 8;
    obj << "usemtl light\nf " << l << ' ' << l + 2 << ' ' << l + 1 << "\nf " << l << ' ' << l + 3
        << ' ' << l + 2 << '\n';
  }
  return obj.str();
}

// A ground plane `width` wide under the unit room, its vertices from `first` on.
std::string groundPlane(double width, int first) {
  std::ostringstream obj;
  obj.precision(17);
  const double h = width / 2;
  for (auto [x, y] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}})
    obj << "v " << 0.5 + x << ' ' << 0.5 + y << " -0.01\n";
  obj << "usemtl ground\nf " << first << ' ' << first + 1 << ' ' << first + 2 << "\nf " << first
      << ' ' << first + 2 << ' ' << first + 3 << '\n';
  return obj.str();
}

const char* const kMaterials =
    "newmtl glow\nKd 0.5 0.5 0.5\nKe 1 1 1\nnewmtl wall\nKd 0.5 0.5 0.5\n"
    "newmtl light\nKd 0 0 0\nKe 10 10 10\nnewmtl ground\nKd 0.5 0.5 0.5\n";

// Area-weighted mean B (red) over the patches with E = 0 and a centroid inside the unit room.
double roomMean(const Result& result) {
  double sum = 0, area = 0;
  for (int64_t t = 0; t < result.mesh.triangleCount(); ++t) {
    const Vec3 c = result.mesh.centroid(t);
    if (result.mesh.emission[t][0] > 0 || c.z < -1e-3 || c.x < -1e-3 || c.x > 1.001 ||
        c.y < -1e-3 || c.y > 1.001)
      continue;
    sum += result.area[t] * result.radiosity[t][0];
    area += result.area[t];
  }
  return sum / area;
}

// A closed room whose walls all emit E = 1 with ρ = 0.5 has B = E / (1 − ρ) = 2 exactly, on a
// ground plane of any size: a 1e6-wide one used to make every wall "degenerate" (dropped:
// B = 0 everywhere, exit 0), then its rays, lifted by 1e-5 of the scene's size, left the room.
TEST_F(EndToEnd, RoomOnAHugeGroundPlaneKeepsItsTrianglesAndItsLight) {
  std::ofstream(path("m.mtl")) << kMaterials;
  std::ofstream(path("glow.obj")) << "mtllib m.mtl\n"
                                  << room(1, 1, "glow", false) << groundPlane(1e6, 9);
  ProgramRun run =
      radiosity(2, "solve " + path("glow.obj") + " --patches 100 --rays 64 -o " + path("glow.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(run.output.find("degenerate"), std::string::npos) << run.output;
  const Result glow = readResult(path("glow.h5"));
  int walls = 0;
  for (int64_t t = 0; t < glow.mesh.triangleCount(); ++t) {
    if (glow.mesh.emission[t][0] == 0) continue;
    ++walls;
    EXPECT_NEAR(glow.radiosity[t][0], 2.0, 0.2) << "patch " << t;
  }
  EXPECT_EQ(walls, 12);

  // A room lit by a lamp: on the huge plane as on a small one (the room is closed).
  std::ofstream(path("huge.obj")) << "mtllib m.mtl\n"
                                  << room(1, 1, "wall", true) << groundPlane(1e6, 13);
  std::ofstream(path("small.obj")) << "mtllib m.mtl\n"
                                   << room(1, 1, "wall", true) << groundPlane(4, 13);
  for (const char* name : {"huge", "small"}) {
    run = radiosity(2, "solve " + path(std::string(name) + ".obj") +
                           " --patches 300 --rays 256 -o " + path(std::string(name) + ".h5"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
  }
  const double huge = roomMean(readResult(path("huge.h5")));
  const double small = roomMean(readResult(path("small.h5")));
  EXPECT_GT(small, 0.03);
  EXPECT_NEAR(huge, small, 0.05 * small);
}

// A room wound inside out (every face's vertices clockwise seen from inside) lets every ray
// out and hits no back face: B = E everywhere, which used to pass without a word. It is warned
// about, naming the winding; the same room the right way round is not.
TEST_F(EndToEnd, ARoomWoundInsideOutIsWarnedAbout) {
  const std::string lamp = "newmtl lamp\nKd 0 0 0\nKe 60 55 50\n";
  testing::writeRoomObj(
      path("room.obj"), path("room.mtl"), lamp,
      {{"lamp",
        {{{1.75, 2.99, 1.75}, {2.25, 2.99, 1.75}, {2.25, 2.99, 2.25}, {1.75, 2.99, 2.25}}}}});
  std::ifstream in(path("room.obj"));
  std::ofstream out(path("inside_out.obj"));
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("f ", 0) != 0) {
      out << line << "\n";
      continue;
    }
    std::istringstream corners(line.substr(2));
    std::vector<std::string> face{std::istream_iterator<std::string>(corners), {}};
    out << "f";
    for (auto corner = face.rbegin(); corner != face.rend(); ++corner) out << " " << *corner;
    out << "\n";
  }
  out.close();
  ProgramRun right = radiosity(2, "solve " + path("room.obj") + " --rays 64 -o " + path("r.h5"));
  ASSERT_EQ(right.exitCode, 0) << right.output;
  EXPECT_EQ(right.output.find("left the scene"), std::string::npos) << right.output;
  ProgramRun wrong =
      radiosity(2, "solve " + path("inside_out.obj") + " --rays 64 -o " + path("w.h5"));
  ASSERT_EQ(wrong.exitCode, 0) << wrong.output;
  EXPECT_NE(wrong.output.find("% of the rays left the scene without hitting anything"),
            std::string::npos)
      << wrong.output;
  EXPECT_NE(wrong.output.find("counter-clockwise"), std::string::npos) << wrong.output;
}

// The same room at 1e-150 gives the answer at scale 1 ("scene has no triangles" before: the
// area's square underflowed).
TEST_F(EndToEnd, RoomAt1eMinus150GivesTheAnswerOfScaleOne) {
  std::ofstream(path("m.mtl")) << kMaterials;
  std::ofstream(path("one.obj")) << "mtllib m.mtl\n" << room(1, 1, "wall", true);
  std::ofstream(path("tiny.obj")) << "mtllib m.mtl\n" << room(1e-150, 1, "wall", true);
  std::vector<Result> results;
  for (const char* name : {"one", "tiny"}) {
    ProgramRun run =
        radiosity(1, "solve " + path(std::string(name) + ".obj") + " --patches 200 --rays 32 -o " +
                         path(std::string(name) + ".h5"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.push_back(readResult(path(std::string(name) + ".h5")));
  }
  ASSERT_EQ(results[0].radiosity.size(), results[1].radiosity.size());
  for (size_t t = 0; t < results[0].radiosity.size(); ++t) {
    EXPECT_NEAR(results[1].radiosity[t][0], results[0].radiosity[t][0],
                1e-9 * (1 + results[0].radiosity[t][0]))
        << "patch " << t;
    EXPECT_NEAR(1e300 * results[1].area[t], results[0].area[t], 1e-9 * results[0].area[t]);
  }
}

// One vertex at 1e30 squeezes the rest of the scene below what float tracing resolves: a clear
// refusal naming the file and why ("scene has no triangles" before).
TEST_F(EndToEnd, AVertexAt1e30IsRefusedAsUntraceable) {
  std::ofstream(path("m.mtl")) << kMaterials;
  std::ofstream(path("far.obj")) << "mtllib m.mtl\n"
                                 << room(1, 1, "wall", true)
                                 << "v 1e30 1e30 0\nv 1e30 0 1e30\nusemtl wall\nf 1 13 14\n";
  ProgramRun run = radiosity(2, "solve " + path("far.obj") + " -o " + path("far.h5"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("far.obj"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("traced in float"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("far.h5")));
}

// Overwrites value `index` of the float64 dataset `name` of an HDF5 file.
void overwrite(const std::string& file, const char* name, hsize_t index, double value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t space = H5Dget_space(d);
  const hsize_t count = 1;
  const hsize_t coords[2] = {index / 3, index % 3};
  H5Sselect_elements(space, H5S_SELECT_SET, 1, coords);
  const hid_t memory = H5Screate_simple(1, &count, nullptr);
  EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, &value), 0);
  H5Sclose(memory);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

// A result vertex at 1e31 (a damaged or hand-made file): verify used to abort inside Embree
// (ray.valid(), 134); verify and render refuse it, naming the file (exit 3).
TEST_F(EndToEnd, TracersRefuseAResultTheTracingFrameCannotHold) {
  const std::string result = path("r.h5");
  ProgramRun run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o " + result);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  ASSERT_NO_FATAL_FAILURE(overwrite(result, "/mesh/vertices", 0, 1e31));
  for (const std::string& command :
       {"verify " + result + " --patches 4 --paths 4 --csv " + path("v.csv"),
        "render " + result + " -o " + path("r.png") + " --width 16 --height 16"}) {
    run = radiosity(2, command);
    EXPECT_EQ(run.exitCode, 3) << command << "\n" << run.output;
    EXPECT_NE(run.output.find("r.h5"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("1e+31"), std::string::npos) << run.output;
  }
  EXPECT_FALSE(fs::exists(path("v.csv")));
  EXPECT_FALSE(fs::exists(path("r.png")));
}

// A result whose attribute messages a byte-flip fuzzer damaged (tests/data): HDF5 crashed in
// H5Aiterate2 freeing its half-built attribute table, and `info` segfaulted.
TEST_F(EndToEnd, InfoOnDamagedAttributesIsABadInputNotACrash) {
  fs::copy_file(std::string(SOURCE_DIR) + "/tests/data/damaged_attributes_result.h5",
                path("damaged.h5"));
  for (int ranks : {1, 2}) {
    ProgramRun run = radiosity(ranks, "info " + path("damaged.h5"));
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("damaged.h5: H5Aiterate2: the attributes are damaged"),
              std::string::npos)
        << run.output;
  }
}

// Emission is linear in the answer but the solver's norms square it: above 1e100 a clear
// refusal naming the MTL line (E = 1e200 used to end in exit 4, "iterate is not finite"); at
// 1e100 the answer.
TEST_F(EndToEnd, EmissionBeyondTheSolversRangeIsRefusedUpFront) {
  std::ofstream(path("hot.mtl")) << "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKe 1e200 1 1\n";
  std::ofstream(path("hot.obj")) << "mtllib hot.mtl\n" << room(1, 1, "wall", true);
  ProgramRun run = radiosity(1, "solve " + path("hot.obj") + " -o " + path("hot.h5"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("hot.mtl:4"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("1e100"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("hot.h5")));

  std::ofstream(path("hot.mtl")) << "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKe 1e100 1 1\n";
  run = radiosity(1, "solve " + path("hot.obj") + " --patches 100 --rays 16 -o " + path("hot.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result hot = readResult(path("hot.h5"));
  EXPECT_GT(roomMean(hot), 1e97);
  EXPECT_TRUE(std::isfinite(roomMean(hot)));
}

// The XDMF sidecar stays well-formed XML and names the file right for names with markup
// characters and newlines; a name that is not UTF-8 is refused before the solve (exit 2).
TEST_F(EndToEnd, SidecarNamesAreEscapedAndEncoded) {
  const std::string odd = path("a<&b\nc.h5");
  ProgramRun run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o '" + odd + "'");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const std::string sidecar = testing::readText(path("a<&b\nc.xmf"));
  EXPECT_NE(sidecar.find(">a&lt;&amp;b&#10;c.h5:/display/vertices</DataItem>"), std::string::npos)
      << sidecar;
  EXPECT_EQ(sidecar.find("a<&b"), std::string::npos) << sidecar;

  run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o " + path("bad\xff.h5"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("not UTF-8"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("bad\xff.h5")));
}

// `xdmf` checks the display triangles' indices as the patches' (ParaView read out of range).
TEST_F(EndToEnd, XdmfRangeChecksTheDisplayTriangles) {
  const std::string result = path("r.h5");
  ProgramRun run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o " + result);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const hid_t f = H5Fopen(result.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, "/display/triangles", H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t space = H5Dget_space(d);
  const hsize_t one = 1, at[2] = {5, 1};
  H5Sselect_elements(space, H5S_SELECT_SET, 1, at);
  const hid_t memory = H5Screate_simple(1, &one, nullptr);
  const int64_t far = 1000000;
  EXPECT_GE(H5Dwrite(d, H5T_NATIVE_INT64, memory, space, H5P_DEFAULT, &far), 0);
  H5Sclose(memory);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  run = radiosity(1, "xdmf " + result + " -o " + path("r2.xmf"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("/display/triangles row 5 refers to vertex 1000000"), std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(path("r2.xmf")));
}

// Sets the string attribute `name` of the root of an HDF5 file to `text`.
void setRootText(const std::string& file, const char* name, const std::string& text) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, text.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attribute = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(attribute, 0);
  EXPECT_GE(H5Awrite(attribute, type, text.data()), 0);
  H5Aclose(attribute);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(f);
}

// `info` prints text from the file escaped (an ESC sequence cleared the terminal) and cut (a
// 100 kB value was printed whole).
TEST_F(EndToEnd, InfoEscapesAndCutsTheFilesText) {
  const std::string result = path("r.h5");
  ProgramRun run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o " + result);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  ASSERT_NO_FATAL_FAILURE(setRootText(result, "note\x1b[1m", "clear\x1b[2J\xff"));
  ASSERT_NO_FATAL_FAILURE(setRootText(result, "long", std::string(30000, 'x')));
  run = radiosity(1, "info " + result);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(run.output.find('\x1b'), std::string::npos);
  EXPECT_NE(run.output.find("note\\x1B[1m = \"clear\\x1B[2J\\xFF\""), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("... (30000 bytes)"), std::string::npos);
  EXPECT_LT(run.output.size(), 15000u);
}

// Minor messages made true: an --up of 1e300 or 1e-300 is a direction, not "parallel"; a
// --stop-after the parser refuses is not called out of a range it is in; `scene -o ' lead.obj'`
// writes an OBJ that reads back.
TEST_F(EndToEnd, MinorMessagesAreTrue) {
  const std::string result = path("r.h5");
  ProgramRun run = radiosity(1, "solve builtin:box --patches 48 --rays 16 -o " + result);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  for (const char* up : {"1e300 0 0", "0 1e-300 0"}) {
    run = radiosity(
        1, "render " + result + " -o " + path("r.png") + " --width 16 --height 16 --up " + up);
    EXPECT_EQ(run.exitCode, 0) << up << "\n" << run.output;
  }
  run = radiosity(
      1, "solve builtin:box --checkpoint " + path("c.h5") + " --stop-after 1e9 -o " + path("s.h5"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_EQ(run.output.find("(0, 1e9]"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("no exponents"), std::string::npos) << run.output;

  run = radiosity(1, "scene builtin:box -o '" + path(" lead.obj") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  run = radiosity(1,
                  "solve '" + path(" lead.obj") + "' --patches 48 --rays 16 -o " + path("lead.h5"));
  EXPECT_EQ(run.exitCode, 0) << run.output;
}

// A scene file named in Latin-1 (é as the byte E9; OFF and PLY scenes take their file's name
// as their label) is labelled in UTF-8 text, the byte as \xE9, with a warning naming it; the
// name used to be stored as it was, marked UTF-8. (validateScene does it for every loader.)
TEST_F(EndToEnd, LabelsThatAreNotUtf8AreStoredAsUtf8Text) {
  const std::string scene = path("caf\xE9.off");
  std::ofstream(scene) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  ProgramRun run = radiosity(1, "solve '" + scene + "' --patches 8 --rays 16 -o " + path("r.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("is not UTF-8 text"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("caf\\xE9.off"), std::string::npos) << run.output;
}

// A 100 kB value or name in an option or a scene is quoted cut, not echoed whole, and a
// terminal escape in an option's value is shown as \x1B.
TEST_F(EndToEnd, HundredKilobyteValuesAreCutInMessages) {
  const std::string huge(100000, 'x');
  std::ofstream(path("material.obj"))
      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl " << huge << "\nf 1 2 3\n";
  const std::string options = " --patches 16 --rays 16 -o " + path("r.h5");
  for (const std::string& arguments :
       {"solve builtin:cornell --rays " + huge, "solve builtin:" + huge + options,
        "solve builtin:cornell --solver " + huge, "solve " + path("material.obj") + options,
        "solve " + path(huge + ".obj") + options}) {
    ProgramRun run = radiosity(1, arguments);
    EXPECT_NE(run.exitCode, 0) << run.output.substr(0, 400);
    EXPECT_LT(run.output.size(), 2000u) << run.output.substr(0, 400);
    EXPECT_NE(run.output.find("(100"), std::string::npos) << run.output.substr(0, 400);
  }
  ProgramRun run = radiosity(1, "solve builtin:cornell --solver '\x1b[2J'" + options);
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_EQ(run.output.find('\x1b'), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\\x1B"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace radiosity
