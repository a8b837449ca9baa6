// The HDF5 scene file's refusals (io/store/scene_file.h): malformed and foreign files are refused
// on every rank with an InputError naming the file, the dataset and the problem; degenerate
// triangles are dropped as the other loaders drop them; damaged data is refused or read as a
// valid scene. Runs on one rank and on N with `mpirun -n N build/tests/io_scene_file_refusal_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "expect_error.h"
#include "io/scene/scene.h"
#include "io/store/result.h"
#include "io/store/scene_file.h"
#include "scene_file_fixture.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::expectInputError;
using testing::oddMaterials;
using testing::rewritten;
using testing::SceneFileTest;
using testing::worldRank;
using testing::writeText;

/// Replaces dataset `name` by one of `type` and shape `dims`, filled with zeros.
std::function<void(hid_t)> replace(const char* name, hid_t type, std::vector<hsize_t> dims) {
  return [=](hid_t f) {
    ASSERT_GE(H5Ldelete(f, name, H5P_DEFAULT), 0) << name;
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t dataset = H5Dcreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(dataset, 0) << name;
    hsize_t n = 1;
    for (hsize_t d : dims) n *= d;
    std::vector<double> zeros(n);
    ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
    H5Dclose(dataset);
    H5Sclose(space);
  };
}

/// Replaces dataset `name` by one of `type` and shape `dims` that is never written: the file
/// stores none of it (a 10 kB file can claim 2·10^7 triangles so).
std::function<void(hid_t)> claim(const char* name, hid_t type, std::vector<hsize_t> dims) {
  return [=](hid_t f) {
    ASSERT_GE(H5Ldelete(f, name, H5P_DEFAULT), 0) << name;
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t dataset = H5Dcreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(dataset, 0) << name;
    H5Dclose(dataset);
    H5Sclose(space);
  };
}

std::function<void(hid_t)> remove(const char* name) {
  return [=](hid_t f) { ASSERT_GE(H5Ldelete(f, name, H5P_DEFAULT), 0) << name; };
}

std::function<void(hid_t)> setRootAttribute(const char* name, const std::string& text) {
  return [=](hid_t f) {
    if (H5Aexists(f, name) > 0) H5Adelete(f, name);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, std::max<size_t>(text.size(), 1));
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Awrite(attribute, type, text.c_str()), 0);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
  };
}

TEST_F(SceneFileTest, MalformedFilesAreRefusedNamingFileDatasetAndProblem) {
  const Mesh cornell = loadScene("builtin:cornell");
  const int64_t nv = static_cast<int64_t>(cornell.vertices.size());
  const std::string good = write("good.h5", cornell);
  struct Case {
    const char* name;
    std::function<void(hid_t)> damage;
    std::vector<std::string> mentions;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
      {"missing.h5", remove("/mesh/triangles"), {"missing dataset /mesh/triangles"}},
      {"no_emission.h5", remove("/materials/emission"), {"missing dataset /materials/emission"}},
      {"shape.h5",
       replace("/mesh/vertices", H5T_IEEE_F64LE, {static_cast<hsize_t>(nv), 2}),
       {"/mesh/vertices", "shape [60, 2]", "expected [n, 3]"}},
      {"rows.h5",
       replace("/mesh/material", H5T_STD_I32LE, {5}),
       {"/mesh/material", "shape [5]", "expected [78]"}},
      {"class.h5",
       replace("/mesh/triangles", H5T_IEEE_F64LE, {78, 3}),
       {"/mesh/triangles", "holds float64", "expected int64"}},
      {"index.h5",
       rewritten<int64_t>("/mesh/triangles", H5T_NATIVE_INT64,
                          [nv](std::vector<int64_t>& v) { v[3 * 40 + 2] = nv; }),
       {"/mesh/triangles", "row 40", "refers to vertex 60", "60 vertices"}},
      {"negative_index.h5",
       rewritten<int64_t>("/mesh/triangles", H5T_NATIVE_INT64,
                          [](std::vector<int64_t>& v) { v[0] = -1; }),
       {"/mesh/triangles", "row 0", "refers to vertex -1"}},
      {"nan.h5",
       rewritten<double>("/mesh/vertices", H5T_NATIVE_DOUBLE,
                         [nan](std::vector<double>& v) { v[3 * 7 + 1] = nan; }),
       {"/mesh/vertices", "row 7", "coordinate nan", "finite"}},
      // The last row, which only the last rank reads when there are several: all must refuse.
      {"nan_last.h5",
       rewritten<double>("/mesh/vertices", H5T_NATIVE_DOUBLE,
                         [nan](std::vector<double>& v) { v.back() = -nan; }),
       {"/mesh/vertices", "row 59", "coordinate"}},
      {"huge.h5",
       rewritten<double>("/mesh/vertices", H5T_NATIVE_DOUBLE,
                         [](std::vector<double>& v) { v[4] = 2e30; }),
       {"/mesh/vertices", "row 1", "2e+30", "1e30"}},
      {"emission.h5",
       rewritten<double>("/materials/emission", H5T_NATIVE_DOUBLE,
                         [](std::vector<double>& v) { v[3 * 2 + 1] = -1; }),
       {"/materials/emission", "row 2 channel 1", "-1", ">= 0"}},
      {"infinite.h5",
       rewritten<double>("/materials/emission", H5T_NATIVE_DOUBLE,
                         [](std::vector<double>& v) { v[0] = HUGE_VAL; }),
       {"/materials/emission", "row 0 channel 0", "inf"}},
      {"reflectance.h5",
       rewritten<double>("/materials/reflectance", H5T_NATIVE_DOUBLE,
                         [](std::vector<double>& v) { v[5] = 1.5; }),
       {"/materials/reflectance", "row 1 channel 2", "1.5", "[0, 1]"}},
      {"material.h5",
       rewritten<int32_t>("/mesh/material", H5T_NATIVE_INT32,
                          [](std::vector<int32_t>& v) { v.back() = 8; }),
       {"/mesh/material", "row 77", "holds 8", "/materials (8 rows)"}},
      {"label.h5",
       rewritten<int32_t>("/materials/label", H5T_NATIVE_INT32,
                          [](std::vector<int32_t>& v) { v[3] = -2; }),
       {"/materials/label", "row 3", "holds -2", "/labels/name"}},
      {"source_face.h5",
       rewritten<int64_t>("/mesh/source_face", H5T_NATIVE_INT64,
                          [](std::vector<int64_t>& v) { v[9] = -5; }),
       {"/mesh/source_face", "row 9", "-5"}},
      {"names.h5", remove("/labels/name"), {"/materials/label without /labels/name"}},
      // Sizes the file claims but does not hold: refused before anything is allocated.
      {"claims.h5",
       claim("/mesh/vertices", H5T_IEEE_F64LE, {20000000, 3}),
       {"/mesh/vertices", "claims 60000000 values", "stores 0 bytes"}},
      {"claimed_names.h5",
       claim("/labels/name", H5T_C_S1, {400000000}),
       {"/labels/name", "claims 400000000 values"}},
      {"name_type.h5",
       replace("/labels/name", H5T_STD_I32LE, {8}),
       {"/labels/name", "holds int32", "expected strings"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string bad = damaged(good, c.name, c.damage);
    std::vector<std::string> mentions = c.mentions;
    mentions.push_back(bad);
    expectInputError([&] { loadScene(bad, MPI_COMM_WORLD); }, mentions);
  }
}

TEST_F(SceneFileTest, OtherFilesAreNotScenes) {
  const std::string good = write("good.h5", loadScene("builtin:box"));
  // A result file: HDF5 with /mesh, but no scene.
  writeResult(MPI_COMM_WORLD, path("result.h5"), Mesh(), LocalSolution(), ResultAttributes{});
  if (worldRank() == 0) writeText(path("words.h5"), "not HDF5 at all\n");
  if (worldRank() == 0) fs::create_directories(path("folder.h5"));
  const std::string checkpoint =
      damaged(good, "checkpoint.h5", setRootAttribute("kind", "radiosity checkpoint"));
  const std::string version = damaged(good, "version.h5", [](hid_t f) {
    const hid_t attribute = H5Aopen(f, "format_version", H5P_DEFAULT);
    const int two = 2;
    ASSERT_GE(H5Awrite(attribute, H5T_NATIVE_INT, &two), 0);
    H5Aclose(attribute);
  });
  if (worldRank() == 0) {
    fs::copy_file(good, path("cut.h5"));
    fs::resize_file(path("cut.h5"), fs::file_size(good) / 2);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  auto read = [](const std::string& file) {
    return [file] { readSceneFile(MPI_COMM_WORLD, file); };
  };
  expectInputError(read(path("result.h5")), {path("result.h5"), "not a scene file", "kind"});
  expectInputError(read(checkpoint), {checkpoint, "not a scene file", "radiosity checkpoint"});
  expectInputError(read(version), {version, "format_version 2"});
  expectInputError(read(path("words.h5")), {path("words.h5"), "not an HDF5 file"});
  expectInputError(read(path("absent.h5")), {path("absent.h5"), "no such file"});
  expectInputError(read(path("folder.h5")), {path("folder.h5"), "is a directory"});
  expectInputError(read(path("cut.h5")), {path("cut.h5")});
}

TEST_F(SceneFileTest, DegenerateTrianglesAreDroppedAsTheOtherLoadersDo) {
  Mesh mesh = oddMaterials();
  mesh.triangles[5] = {3, 3, 4};  // names a vertex twice: no area
  mesh.triangles[11] = {6, 7, 6};
  const Mesh back = readSceneFile(MPI_COMM_WORLD, write("flat.h5", mesh));
  EXPECT_EQ(back.triangleCount(), mesh.triangleCount() - 2);
  ASSERT_EQ(back.warnings.size(), 1u);
  EXPECT_NE(back.warnings[0].find("dropped 2 degenerate"), std::string::npos) << back.warnings[0];
  EXPECT_EQ(back.sourceFace[5], mesh.sourceFace[6]);  // the others keep their faces
  Mesh flat = oddMaterials();
  for (Triangle& t : flat.triangles) t = {0, 0, 1};
  const std::string none = write("none.h5", flat);
  expectInputError([&] { readSceneFile(MPI_COMM_WORLD, none); }, {none, "no triangles"});
}

TEST_F(SceneFileTest, DamagedDataIsRefusedOrReadAsAValidScene) {
  // Bytes flipped at random in the datasets' data (the HDF5 metadata is HDF5's to check): each
  // read ends in an InputError, or in a mesh every later stage can take.
  const std::string good = write("good.h5", loadScene("builtin:cornell"));
  std::vector<std::pair<haddr_t, hsize_t>> extents;
  if (worldRank() == 0) {
    const hid_t f = H5Fopen(good.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    for (const char* name :
         {"/mesh/vertices", "/mesh/triangles", "/mesh/material", "/mesh/source_face",
          "/materials/reflectance", "/materials/emission", "/materials/label", "/labels/name"}) {
      const hid_t dataset = H5Dopen2(f, name, H5P_DEFAULT);
      extents.emplace_back(H5Dget_offset(dataset), H5Dget_storage_size(dataset));
      ASSERT_NE(extents.back().first, HADDR_UNDEF) << name;
      H5Dclose(dataset);
    }
    H5Fclose(f);
  }
  std::mt19937_64 random(20240515);
  int refused = 0, read = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const std::string bad = path("flipped.h5");
    if (worldRank() == 0) {
      fs::copy_file(good, bad, fs::copy_options::overwrite_existing);
      std::fstream stream(bad, std::ios::in | std::ios::out | std::ios::binary);
      for (int flip = 0; flip < 1 + trial % 4; ++flip) {
        const auto& [address, size] = extents[random() % extents.size()];
        const auto where = static_cast<std::streamoff>(address + random() % size);
        stream.seekg(where);
        const char byte = static_cast<char>(stream.get() ^ (1 << (random() % 8)));
        stream.seekp(where);
        stream.put(byte);
      }
    }
    MPI_Barrier(MPI_COMM_WORLD);
    try {
      const Mesh mesh = readSceneFile(MPI_COMM_WORLD, bad);
      ++read;
      const auto nv = static_cast<int64_t>(mesh.vertices.size());
      for (const Vec3& v : mesh.vertices)
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(v[k]));
      for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int64_t i : mesh.triangles[t]) ASSERT_TRUE(i >= 0 && i < nv);
        ASSERT_GT(mesh.area(t), 0);
        ASSERT_GE(mesh.sourceFace[t], 0);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(mesh.reflectance[t][c] >= 0 && mesh.reflectance[t][c] <= 1);
          ASSERT_TRUE(mesh.emission[t][c] >= 0 && std::isfinite(mesh.emission[t][c]));
        }
        ASSERT_TRUE(mesh.label[t] >= 0 && size_t(mesh.label[t]) < mesh.labelNames.size());
      }
    } catch (const InputError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(read, 0);
}

}  // namespace
}  // namespace radiosity
