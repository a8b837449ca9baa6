// The display mesh (smooth radiosity as point data, split at creases) and the XDMF sidecar every
// result gets, on any number of ranks: what ParaView reads must be what the renderer shows.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "core/channels.h"
#include "core/corner_radiosity.h"
#include "core/error.h"
#include "io/store/display_writer.h"
#include "io/store/hdf5_read.h"
#include "io/store/xdmf.h"
#include "result_fixture.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::distribute;
using testing::namesIn;
using testing::Owned;
using testing::readText;
using testing::ResultFileTest;
using testing::someAttributes;
using testing::strip;

// Two triangles sharing the edge (0,1): in the plane z = 0 or, with `folded`, the second one
// turned up to the plane x = 0 (a 90° crease).
Mesh hinge(bool folded) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, folded ? Vec3{0, 0, 1} : Vec3{-1, 0, 0}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}};
  mesh.reflectance.assign(2, {0.5, 0.5, 0.5});
  mesh.emission.assign(2, {0, 0, 0});
  return mesh;
}

DisplayMesh displayOf(const Mesh& mesh, const std::vector<Rgb>& b) {
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  return displayMesh(mesh, cornerRadiosity(mesh, normal, area, b, materialSurfaces(mesh)));
}

TEST(DisplayMesh, OneSurfaceSharesItsVerticesAndAveragesThem) {
  const DisplayMesh d = displayOf(hinge(false), {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 4u);  // the shared edge's two vertices stay shared
  const Triangle &a = d.triangles[0], &b = d.triangles[1];
  EXPECT_EQ(a[0], b[0]);
  EXPECT_EQ(a[2], b[1]);
  EXPECT_EQ(d.radiosity[a[0]], (Rgb{2, 2, 2}));  // equal areas: the plain mean
  EXPECT_EQ(d.radiosity[a[1]], (Rgb{1, 1, 1}));  // a corner of the first triangle only
  EXPECT_EQ(d.radiosity[b[2]], (Rgb{3, 3, 3}));
}

TEST(DisplayMesh, ACreaseSplitsItsVertices) {
  const Mesh mesh = hinge(true);
  const DisplayMesh d = displayOf(mesh, {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 6u);
  for (int64_t t = 0; t < 2; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int64_t v = d.triangles[t][k];
      EXPECT_EQ(d.radiosity[v], (t == 0 ? Rgb{1, 1, 1} : Rgb{3, 3, 3}));  // no averaging across
      const Vec3 &p = d.vertices[v], &q = mesh.vertices[mesh.triangles[t][k]];
      EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z);
    }
  }
}

// A light and the ceiling around it, coplanar and sharing an edge: B jumps there, and ParaView
// must not smooth it away any more than the renderer does.
TEST(DisplayMesh, AChangeOfMaterialSplitsItsVertices) {
  Mesh mesh = hinge(false);
  mesh.emission[1] = {2, 2, 2};
  const DisplayMesh d = displayOf(mesh, {{1, 1, 1}, {3, 3, 3}});
  ASSERT_EQ(d.vertices.size(), 6u);
  for (int64_t t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(d.radiosity[d.triangles[t][k]], (t == 0 ? Rgb{1, 1, 1} : Rgb{3, 3, 3}));
}

TEST(DisplayMesh, RadiosityNearTheLargestDoubleStaysFinite) {
  const DisplayMesh d = displayOf(hinge(false), {{1e308, 1, 1}, {1.5e308, 1, 1}});
  for (const Rgb& b : d.radiosity) EXPECT_TRUE(std::isfinite(b[0]) && b[0] >= 1e308) << b[0];
}

// Dataset `name` of [n, `columns`] (0: [n]).
template <class T>
std::vector<T> readAll(const fs::path& file, const std::string& name, int columns = 3) {
  h5::Handle handle = h5::openFile(file.string(), "result file");
  int64_t rows = -1;
  const hid_t type = std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64;
  return h5::readDataset<T>(handle.get(), file.string(), name, type, columns, rows);
}

// The luminance /display/luminance_tonemapped shows as 0.5, as docs/result-format.md defines it:
// the area-weighted geometric mean of the luminance of the patches that reflect and do not emit,
// Σ A log Y summed a display chunk at a time and the chunks' sums in order.
double expectedMidpoint(const Mesh& mesh, const std::vector<Rgb>& b) {
  const int64_t np = mesh.triangleCount();
  double logSum = 0, area = 0;
  for (int64_t from = 0; from < np; from += kDisplayChunk) {
    double chunkLog = 0, chunkArea = 0;
    for (int64_t p = from; p < std::min(np, from + kDisplayChunk); ++p) {
      const double y = luminance(b[p]);
      const Rgb& rho = mesh.reflectance[p];
      if (y > 0 && mesh.emission[p] == Rgb{0, 0, 0} && std::max({rho[0], rho[1], rho[2]}) > 0) {
        chunkLog += mesh.area(p) * std::log(y);
        chunkArea += mesh.area(p);
      }
    }
    logSum += chunkLog;
    area += chunkArea;
  }
  return std::exp(logSum / area);
}

double midpointIn(const fs::path& file) {
  h5::Handle handle = h5::openFile(file.string(), "result file");
  const h5::Handle dataset =
      h5::own(H5Dopen2(handle.get(), "/display/luminance_tonemapped", H5P_DEFAULT), "H5Dopen2");
  return h5::readAttribute<double>(dataset.get(), file.string(), "midpoint");
}

// The file's display mesh is the renderer's corner radiosity, whatever the ranks' blocks.
TEST_F(ResultFileTest, DisplayMeshIsTheRenderersCornerRadiosity) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());
  const DisplayMesh expected = displayOf(mesh, testing::radiosityOf(mesh));
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto vertices = readAll<double>(path, "/display/vertices");
  const auto radiosity = readAll<double>(path, "/display/radiosity");
  ASSERT_EQ(triangles.size(), 3 * static_cast<size_t>(mesh.triangleCount()));
  ASSERT_EQ(vertices.size(), 3 * expected.vertices.size());
  ASSERT_EQ(radiosity.size(), 3 * expected.vertices.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<size_t>(triangles[3 * t + k]);
      const Vec3& p = mesh.vertices[mesh.triangles[t][k]];
      EXPECT_EQ(vertices[3 * v], p.x);
      EXPECT_EQ(vertices[3 * v + 1], p.y);
      EXPECT_EQ(vertices[3 * v + 2], p.z);
      const Rgb& b = expected.radiosity[expected.triangles[t][k]];
      for (int c = 0; c < 3; ++c) EXPECT_EQ(radiosity[3 * v + c], b[c]) << t << " " << k;
    }
  }
}

// A scene of more patches than a display chunk: the file holds each chunk's display mesh, one
// after the other (its vertices shared inside the chunk), whatever the ranks' blocks; every
// corner shows the whole scene's corner radiosity at its own position.
TEST_F(ResultFileTest, DisplayMeshOfAScenePastAChunkIsTheSameOnAnyRanks) {
  Mesh mesh;
  const int n = 190;  // 2 n² = 72,200 patches: a chunk of 65,536 and part of another
  testing::addSubdividedQuad(mesh, {0, 0, 0}, {double(n), 0, 0}, {0, double(n), 0}, n,
                             {0.5, 0.5, 0.5}, {0, 0, 0});
  const int64_t np = mesh.triangleCount();
  ASSERT_GT(np, kDisplayChunk);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());

  const std::vector<Rgb> b = testing::radiosityOf(mesh);
  const DisplayMesh whole = displayOf(mesh, b);
  const SurfaceIds surfaces = materialSurfaces(mesh);
  const CornerAverages corners(mesh, surfaces, 0, np);
  std::vector<double> expectedVertices, expectedRadiosity;
  std::vector<int64_t> expectedTriangles;
  for (int64_t from = 0; from < np; from += kDisplayChunk) {
    const DisplayMesh chunk = corners.displayMesh(b, from, std::min(np, from + kDisplayChunk));
    const auto shift = static_cast<int64_t>(expectedVertices.size() / 3);
    for (const Triangle& t : chunk.triangles)
      for (int64_t v : t) expectedTriangles.push_back(v + shift);
    for (size_t v = 0; v < chunk.vertices.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        expectedVertices.push_back(c == 0   ? chunk.vertices[v].x
                                   : c == 1 ? chunk.vertices[v].y
                                            : chunk.vertices[v].z);
        expectedRadiosity.push_back(chunk.radiosity[v][c]);
      }
  }
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto vertices = readAll<double>(path, "/display/vertices");
  const auto radiosity = readAll<double>(path, "/display/radiosity");
  EXPECT_EQ(triangles, expectedTriangles);
  EXPECT_EQ(vertices, expectedVertices);
  EXPECT_EQ(radiosity, expectedRadiosity);
  // The tone-mapped luminance, its midpoint summed a chunk at a time: the same bits on any ranks.
  const double midpoint = expectedMidpoint(mesh, b);
  EXPECT_EQ(midpointIn(path), midpoint);
  const auto tonemapped = readAll<double>(path, "/display/luminance_tonemapped", 0);
  ASSERT_EQ(3 * tonemapped.size(), expectedRadiosity.size());
  for (size_t v = 0; v < tonemapped.size(); ++v) {
    const double y = luminance(
        Rgb{expectedRadiosity[3 * v], expectedRadiosity[3 * v + 1], expectedRadiosity[3 * v + 2]});
    ASSERT_EQ(tonemapped[v], y / (y + midpoint)) << v;
  }
  // Only the chunks' shared border repeats vertices: here one row of the grid, 0.5 %.
  EXPECT_GT(vertices.size(), 3 * whole.vertices.size());
  EXPECT_LT(vertices.size(), 3 * whole.vertices.size() * 1.01);
  for (int64_t t = 0; t < np; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<size_t>(triangles[3 * t + k]);
      const Vec3& p = mesh.vertices[mesh.triangles[t][k]];
      ASSERT_EQ(vertices[3 * v], p.x) << t;
      ASSERT_EQ(vertices[3 * v + 1], p.y) << t;
      const Rgb& expected = whole.radiosity[whole.triangles[t][k]];
      for (int c = 0; c < 3; ++c) ASSERT_EQ(radiosity[3 * v + c], expected[c]) << t << " " << k;
    }
}

// The walls at one luminance show as 0.5 (the midpoint is theirs), a light brighter: what a
// colour map spreads over its range, where a linear one leaves the walls in its bottom corner.
TEST_F(ResultFileTest, TonemappedLuminanceShowsTheWallsMidScale) {
  const Mesh mesh = strip();  // patch 3 emits
  Owned owned = distribute(mesh);
  for (size_t k = 0; k < owned.local.radiosity.size(); ++k)
    owned.local.radiosity[k] = owned.local.firstPatch + static_cast<int64_t>(k) == 3
                                   ? Rgb{60, 50, 40}
                                   : Rgb{0.5, 0.5, 0.5};
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  EXPECT_NEAR(midpointIn(path), 0.5, 1e-15);
  const auto triangles = readAll<int64_t>(path, "/display/triangles");
  const auto tonemapped = readAll<double>(path, "/display/luminance_tonemapped", 0);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const double shown = tonemapped[static_cast<size_t>(triangles[3 * t + k])];
      if (t == 3)  // the light's corners, apart from the walls' (another material)
        EXPECT_NEAR(shown, 51.404 / 51.904, 1e-12) << t;  // Y = 0.2126·60 + 0.7152·50 + 0.0722·40
      else
        EXPECT_NEAR(shown, 0.5, 1e-15) << t;
    }
  }
}

// The sidecar names the .h5 by its file name (so the pair can move), shows every /patches
// dataset per cell and the smooth radiosity per point, and never names a temporary.
TEST_F(ResultFileTest, SidecarNamesTheResultAndEveryPatchDataset) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());
  EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"result.h5", "result.xmf"}));
  const std::string text = readText(dir_ / "result.xmf");
  EXPECT_EQ(text.rfind("<?xml", 0), 0u);
  EXPECT_NE(text.find("<Xdmf Version=\"3.0\">"), std::string::npos);
  EXPECT_NE(text.find(">result.h5:/display/triangles<"), std::string::npos) << text;
  EXPECT_NE(text.find(">result.h5:/display/vertices<"), std::string::npos) << text;
  EXPECT_NE(text.find("NumberOfElements=\"10\""), std::string::npos) << text;
  for (const char* name : {"area", "normal", "reflectance", "emission", "radiosity", "irradiance",
                           "source_face", "rank"}) {
    const std::string attribute = std::string("<Attribute Name=\"") + name + "\"";
    const size_t at = text.find(attribute);
    ASSERT_NE(at, std::string::npos) << name;
    EXPECT_EQ(text.substr(text.find("Center=", at), 13), "Center=\"Cell\"") << name;
    EXPECT_NE(text.find(std::string(">result.h5:/patches/") + name + "<"), std::string::npos);
  }
  EXPECT_NE(text.find("<Attribute Name=\"radiosity_smooth\" AttributeType=\"Vector\" "
                      "Center=\"Node\">"),
            std::string::npos);
  EXPECT_EQ(text.find(".tmp."), std::string::npos);
}

// What ParaView shows first: its first point scalar, the tone-mapped luminance; then B, smooth
// and per patch, each with its channels apart as scalars (a hyperslab of B's column), before the
// other datasets.
TEST_F(ResultFileTest, SidecarListsTheTonemappedLuminanceFirstAndBsChannelsByName) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());
  const std::string text = readText(dir_ / "result.xmf");
  const size_t nd = readAll<double>(path, "/display/radiosity").size() / 3;
  const std::string vertices = std::to_string(nd);
  const std::vector<std::string> inOrder = {
      "<Attribute Name=\"luminance_tonemapped\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      "        <DataItem Dimensions=\"" +
          vertices +
          "\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">result.h5:/display/luminance_tonemapped</DataItem>",
      "<Attribute Name=\"radiosity_smooth\" AttributeType=\"Vector\" Center=\"Node\">",
      "<Attribute Name=\"radiosity_smooth_red\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      "        <DataItem Dimensions=\"" +
          vertices +
          " 1\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">result.h5:/display/radiosity|0 0:1 1:" +
          vertices + " 1:" + vertices + " 3</DataItem>",
      "<Attribute Name=\"radiosity_smooth_green\" AttributeType=\"Scalar\" Center=\"Node\">",
      ">result.h5:/display/radiosity|0 1:1 1:",
      "<Attribute Name=\"radiosity_smooth_blue\" AttributeType=\"Scalar\" Center=\"Node\">",
      ">result.h5:/display/radiosity|0 2:1 1:",
      "<Attribute Name=\"radiosity\" AttributeType=\"Vector\" Center=\"Cell\">",
      "<Attribute Name=\"radiosity_red\" AttributeType=\"Scalar\" Center=\"Cell\">",
      "<DataItem Dimensions=\"10 1\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">result.h5:/patches/radiosity|0 0:1 1:10 1:10 3</DataItem>",
      "<Attribute Name=\"radiosity_green\" AttributeType=\"Scalar\" Center=\"Cell\">",
      "<Attribute Name=\"radiosity_blue\" AttributeType=\"Scalar\" Center=\"Cell\">",
      ">result.h5:/patches/radiosity|0 2:1 1:10 1:10 3<",
      "<Attribute Name=\"area\" AttributeType=\"Scalar\" Center=\"Cell\">"};
  EXPECT_EQ(text.find("<Attribute "), text.find(inOrder[0])) << text;
  size_t at = 0;
  for (const std::string& part : inOrder) {
    const size_t found = text.find(part, at);
    ASSERT_NE(found, std::string::npos) << part << "\nafter " << at << " in\n" << text;
    at = found + part.size();
  }
  EXPECT_EQ(text.find("Center=\"Grid\""), std::string::npos);  // no labels: no field data
}

// Units the file states are in the arrays' names (lengths where the scene states its unit; a
// thermal run's W/m^2 and K), none where it states none; a thermal run's one-channel B is what
// ParaView shows first, with no tone-mapped luminance and no channels apart.
TEST_F(ResultFileTest, SidecarNamesCarryTheStatedUnits) {
  const Mesh mesh = strip();
  ResultAttributes attributes = someAttributes();
  attributes.lengthUnit = "m";
  writeResult(MPI_COMM_WORLD, (dir_ / "metres.h5").string(), mesh, distribute(mesh).local,
              attributes);
  std::string text = readText(dir_ / "metres.xmf");
  EXPECT_NE(text.find("<Attribute Name=\"area [m^2]\" AttributeType=\"Scalar\" Center=\"Cell\">"),
            std::string::npos)
      << text;
  for (const char* bare : {"radiosity", "emission", "reflectance", "normal", "source_face"})
    EXPECT_NE(text.find(std::string("<Attribute Name=\"") + bare + "\" "), std::string::npos)
        << bare;
  writeResult(MPI_COMM_WORLD, (dir_ / "unstated.h5").string(), mesh, distribute(mesh).local,
              someAttributes());
  text = readText(dir_ / "unstated.xmf");
  EXPECT_NE(text.find("<Attribute Name=\"area\" "), std::string::npos) << text;
  EXPECT_EQ(text.find(" ["), std::string::npos) << text;

  attributes.channels = 1;
  attributes.thermal = "walls.toml";
  writeResult(MPI_COMM_WORLD, (dir_ / "thermal.h5").string(), mesh, distribute(mesh).local,
              attributes);
  text = readText(dir_ / "thermal.xmf");
  const size_t first = text.find("<Attribute ");
  EXPECT_EQ(first, text.find("<Attribute Name=\"radiosity_smooth [W/m^2]\" "
                             "AttributeType=\"Scalar\" Center=\"Node\">"))
      << text;
  EXPECT_NE(text.find("<Attribute Name=\"radiosity [W/m^2]\" AttributeType=\"Scalar\" "
                      "Center=\"Cell\">"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("<Attribute Name=\"irradiance [W/m^2]\" "), std::string::npos) << text;
  for (const char* absent : {"luminance_tonemapped", "_red", "_green", "_blue", "|"})
    EXPECT_EQ(text.find(absent), std::string::npos) << absent;
}

// The scene's labels, which /patches/group numbers, by name as field data: one array per label,
// "group 1: wall" holding 1 (XML markup in a name escaped).
TEST_F(ResultFileTest, SidecarNamesTheLabelsAsFieldData) {
  Mesh mesh = strip();
  mesh.labelNames = {"floor", "<a&b> \"wall\""};
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) mesh.label.push_back(t % 2);
  Owned owned = distribute(mesh);
  FormFactorOutput output;
  output.groups = {mesh.labelNames, {1, 2}, {0, 0.5, 0.25, 0}, {0, 1e-3, 1e-3, 0}, {}, {}};
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes(), output);
  const std::string text = readText(dir_ / "result.xmf");
  const std::string floor =
      "<Attribute Name=\"group 0: floor\" AttributeType=\"Scalar\" Center=\"Grid\">\n"
      "        <DataItem Dimensions=\"1\" NumberType=\"Int\" Precision=\"4\" "
      "Format=\"XML\">0</DataItem>\n      </Attribute>";
  const std::string wall =
      "<Attribute Name=\"group 1: &lt;a&amp;b&gt; &quot;wall&quot;\" AttributeType=\"Scalar\" "
      "Center=\"Grid\">\n        <DataItem Dimensions=\"1\" NumberType=\"Int\" "
      "Precision=\"4\" Format=\"XML\">1</DataItem>";
  EXPECT_NE(text.find(floor), std::string::npos) << text;
  EXPECT_NE(text.find(wall), std::string::npos) << text;
  EXPECT_NE(text.find("<Attribute Name=\"group\" AttributeType=\"Scalar\" Center=\"Cell\">"),
            std::string::npos);
}

// A result written before /display existed: the patches' mesh, cell data only.
TEST_F(ResultFileTest, SidecarOfAnOlderResultShowsCellData) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, someAttributes());
  MPI_Barrier(MPI_COMM_WORLD);
  if (testing::worldRank() == 0) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_GE(H5Ldelete(file, "/display", H5P_DEFAULT), 0);
    H5Fclose(file);
    const XdmfSidecar sidecar = xdmfFor(path.string(), "old.h5");
    EXPECT_FALSE(sidecar.smooth);
    EXPECT_NE(sidecar.text.find(">old.h5:/mesh/triangles<"), std::string::npos);
    EXPECT_EQ(sidecar.text.find("radiosity_smooth"), std::string::npos);
    EXPECT_EQ(sidecar.text.find("luminance_tonemapped"), std::string::npos);
    // B first, then its channels: the first cell scalar, what ParaView shows, is B's red.
    const size_t first = sidecar.text.find("<Attribute ");
    EXPECT_EQ(first, sidecar.text.find("<Attribute Name=\"radiosity\" AttributeType=\"Vector\""));
    EXPECT_LT(sidecar.text.find("<Attribute Name=\"radiosity_red\" AttributeType=\"Scalar\""),
              sidecar.text.find("<Attribute Name=\"area\""));
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// Every dataset explains itself: `units` and `description` text attributes.
herr_t checkLabels(hid_t object, const char* name, const H5O_info_t* info, void*) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  for (const char* attribute : {"units", "description"}) {
    EXPECT_GT(H5Aexists_by_name(object, name, attribute, H5P_DEFAULT), 0)
        << name << " " << attribute;
  }
  return 0;
}

TEST_F(ResultFileTest, EveryDatasetHasUnitsAndADescription) {
  const Mesh mesh = strip();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local,
              testing::attributesWithHistory());
  if (testing::worldRank() == 0) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_GE(H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_INC, checkLabels, nullptr, H5O_INFO_BASIC), 0);
    H5Fclose(file);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

std::string unitsOf(hid_t file, const char* dataset) {
  const h5::Handle handle = h5::own(H5Dopen2(file, dataset, H5P_DEFAULT), dataset);
  const h5::OpenAttribute units = h5::openAttribute(handle.get(), dataset, "units");
  return h5::readString(units.attribute.get(), units.type.get(), units.what);
}

// Lengths and areas carry the scene's length unit where it is stated, and say so where not.
TEST_F(ResultFileTest, LengthsAreInTheScenesStatedUnit) {
  const Mesh mesh = strip();
  for (const std::string unit : {"m", ""}) {
    const fs::path path = dir_ / ("unit" + unit + ".h5");
    ResultAttributes attributes = testing::attributesWithHistory();
    attributes.lengthUnit = unit;
    writeResult(MPI_COMM_WORLD, path.string(), mesh, distribute(mesh).local, attributes);
    EXPECT_EQ(readResult(path.string()).attributes.lengthUnit, unit);
    if (testing::worldRank() == 0) {
      const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      ASSERT_GE(file, 0);
      const std::string vertices = unitsOf(file, "/mesh/vertices");
      const std::string area = unitsOf(file, "/patches/area");
      if (unit.empty()) {
        EXPECT_EQ(H5Aexists(file, "length_unit"), 0);
        EXPECT_NE(vertices.find("not stated"), std::string::npos) << vertices;
      } else {
        EXPECT_EQ(vertices, "m");
        EXPECT_EQ(area, "m^2");
      }
      H5Fclose(file);
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
}

TEST_F(ResultFileTest, SidecarOfAFileThatIsNoResultIsRefused) {
  if (testing::worldRank() == 0) {
    const fs::path path = dir_ / "other.h5";
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(file);
    try {
      xdmfFor(path.string(), "other.h5");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a result file"), std::string::npos) << e.what();
    }
    EXPECT_THROW(xdmfFor((dir_ / "missing.h5").string(), "missing.h5"), InputError);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace
}  // namespace radiosity
