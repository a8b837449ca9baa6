// The XDMF sidecar every result gets, on any number of ranks: ParaView opens it showing the
// answer (tone-mapped luminance first, B's channels by name, units, the labels), and the units
// and descriptions of every dataset.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/error.h"
#include "io/store/hdf5_read.h"
#include "io/store/xdmf.h"
#include "result_datasets.h"
#include "result_fixture.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
namespace fs = std::filesystem;
using testing::distribute;
using testing::namesIn;
using testing::Owned;
using testing::readAll;
using testing::readText;
using testing::ResultFileTest;
using testing::someAttributes;
using testing::strip;

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
