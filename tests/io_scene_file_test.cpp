// The HDF5 scene file (io/store/scene_file.h): scenes round-trip bit for bit (built-in, through
// OBJ, odd materials, no labels), every rank gets the same mesh, a write that fails leaves
// nothing, and `info` and loadScene know the format. Its refusals are in
// io_scene_file_refusal_test.cpp. Runs on one rank and on N with
// `mpirun -n N build/tests/io_scene_file_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <set>
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

using testing::expectInputError;
using testing::expectSameBits;
using testing::namesIn;
using testing::oddMaterials;
using testing::rewritten;
using testing::SceneFileTest;
using testing::worldRank;
using testing::writeText;

TEST_F(SceneFileTest, BuiltinScenesRoundTripBitForBit) {
  for (const std::string spec :
       {"builtin:cornell", "builtin:rooms?patches=20000", "builtin:sphere?level=2&cap=0.5"}) {
    SCOPED_TRACE(spec);
    const Mesh scene = loadScene(spec);
    ASSERT_TRUE(scene.hasLabels());
    const std::string file = write("scene.h5", scene);
    const Mesh back = loadScene(file, MPI_COMM_WORLD);
    expectSameBits(scene, back);
    EXPECT_TRUE(back.warnings.empty());
  }
}

TEST_F(SceneFileTest, ObjRoundTripsThroughHdf5BitForBit) {
  for (const std::string spec : {"builtin:cornell", "builtin:rooms?patches=20000"}) {
    SCOPED_TRACE(spec);
    const std::string obj = path("scene.obj");
    if (worldRank() == 0) writeSceneObj(loadScene(spec), obj);
    MPI_Barrier(MPI_COMM_WORLD);
    const Mesh fromObj = loadScene(obj, MPI_COMM_WORLD);
    const Mesh back = loadScene(write("scene.h5", fromObj), MPI_COMM_WORLD);
    expectSameBits(fromObj, back);
    MPI_Barrier(MPI_COMM_WORLD);  // every rank has read scene.obj before the next overwrites it
  }
}

TEST_F(SceneFileTest, OddMaterialsAndNoLabelsRoundTrip) {
  Mesh mesh = oddMaterials();
  const Mesh back = readSceneFile(MPI_COMM_WORLD, write("odd.h5", mesh));
  expectSameBits(mesh, back);
  EXPECT_FALSE(back.hasLabels());
  // Every triangle has a material of its own, and the table holds each once.
  mesh.lengthUnit = "ft";
  expectSameBits(mesh, readSceneFile(MPI_COMM_WORLD, write("feet.h5", mesh)));
}

TEST_F(SceneFileTest, MaterialsAreStoredOnceEach) {
  const std::string file = write("cornell.h5", loadScene("builtin:cornell"));
  if (worldRank() == 0) {
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t dataset = H5Dopen2(f, "/materials/reflectance", H5P_DEFAULT);
    const hid_t space = H5Dget_space(dataset);
    hsize_t dims[2] = {};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    EXPECT_EQ(dims[0], 8u);  // floor, ceiling, light, three walls, two blocks
    H5Sclose(space);
    H5Dclose(dataset);
    H5Fclose(f);
  }
}

TEST_F(SceneFileTest, SourceFacesAreOptionalAndStringsMayBeVariableLengthUtf8) {
  const Mesh cornell = loadScene("builtin:cornell");
  const std::string good = write("good.h5", cornell);
  const std::string bare = damaged(good, "bare.h5", [](hid_t f) {
    ASSERT_GE(H5Ldelete(f, "/mesh/source_face", H5P_DEFAULT), 0);
    // What h5py writes for a str and a list of str: variable-length UTF-8 strings.
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    ASSERT_GE(H5Adelete(f, "kind"), 0);
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t kind = H5Acreate2(f, "kind", type, scalar, H5P_DEFAULT, H5P_DEFAULT);
    const char* kindText = "radiosity scene";
    ASSERT_GE(H5Awrite(kind, type, &kindText), 0);
    H5Aclose(kind);
    H5Sclose(scalar);
    ASSERT_GE(H5Ldelete(f, "/labels/name", H5P_DEFAULT), 0);
    const hsize_t count = 8;
    const hid_t space = H5Screate_simple(1, &count, nullptr);
    const hid_t dataset =
        H5Dcreate2(f, "/labels/name", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const char* names[8] = {"a", "", "ccc", "d d", "e", "f", "g", "h"};
    ASSERT_GE(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, names), 0);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Tclose(type);
  });
  EXPECT_TRUE(isSceneFile(bare));
  const Mesh back = readSceneFile(MPI_COMM_WORLD, bare);
  ASSERT_EQ(back.triangleCount(), cornell.triangleCount());
  for (int64_t t = 0; t < back.triangleCount(); ++t) EXPECT_EQ(back.sourceFace[t], t);
  EXPECT_EQ(back.labelNames, (std::vector<std::string>{"a", "", "ccc", "d d", "e", "f", "g", "h"}));
  EXPECT_EQ(back.label, cornell.label);
}

TEST_F(SceneFileTest, AFailedWriteLeavesNothingAndASuccessfulOneReplacesTheFile) {
  const Mesh box = loadScene("builtin:box");
  try {
    write("nodir/box.h5", box);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(path("nodir/box.h5")), std::string::npos) << e.what();
  }
  // An inconsistent mesh is refused before anything is created.
  Mesh broken = box;
  broken.emission.pop_back();
  EXPECT_THROW(write("broken.h5", broken), Error);
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{});
  MPI_Barrier(MPI_COMM_WORLD);  // every rank has looked before rank 0 writes
  if (worldRank() == 0) writeText(path("box.h5"), "an older file");
  MPI_Barrier(MPI_COMM_WORLD);
  expectSameBits(box, readSceneFile(MPI_COMM_WORLD, write("box.h5", box)));
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"box.h5"});
}

TEST_F(SceneFileTest, InfoRecognisesAndDescribesASceneFile) {
  const std::string file = write("cornell.h5", loadScene("builtin:cornell"));
  writeResult(MPI_COMM_WORLD, path("result.h5"), Mesh(), LocalSolution(), ResultAttributes{});
  if (worldRank() == 0) writeText(path("words.h5"), "not HDF5 at all\n");
  const std::string nan = damaged(file, "nan.h5",
                                  rewritten<double>("/mesh/vertices", H5T_NATIVE_DOUBLE,
                                                    [](std::vector<double>& v) { v[2] = NAN; }));
  EXPECT_TRUE(isSceneFile(file));
  EXPECT_TRUE(isSceneFile(nan));
  for (const char* other : {"result.h5", "words.h5", "absent.h5", ""})
    EXPECT_FALSE(isSceneFile(path(other))) << other;
  if (worldRank() != 0) return;  // serial, as `radiosity info` runs it
  const std::string text = describeSceneFile(file);
  for (const char* part : {"scene file (format 1), made from test", "triangles: 78", "vertices: 60",
                           "length unit: mm", "materials: 8", "| light | 2", "radiosity test"})
    EXPECT_NE(text.find(part), std::string::npos) << part << " not in:\n" << text;
  expectInputError([&] { describeSceneFile(nan); }, {nan, "/mesh/vertices", "row 0"});
}

TEST_F(SceneFileTest, LoadSceneTellsHdf5ScenesByTheirExtension) {
  EXPECT_TRUE(isHdf5Scene("a/b.h5"));
  EXPECT_TRUE(isHdf5Scene("B.HDF5"));
  EXPECT_FALSE(isHdf5Scene("b.obj"));
  EXPECT_FALSE(isHdf5Scene("builtin:box?x=1.h5"));
  const Mesh box = loadScene("builtin:box");
  const std::string upper = write("BOX.H5", box);
  expectSameBits(box, loadScene(upper, MPI_COMM_WORLD));
  // The serial loader has no communicator to read one with.
  EXPECT_THROW(loadScene(upper), Error);
  // Any other scene through the collective loader is the serial loader's, on every rank.
  expectSameBits(box, loadScene("builtin:box", MPI_COMM_WORLD));
  expectInputError([&] { loadScene(path("absent.obj"), MPI_COMM_WORLD); }, {"absent.obj"});
}

}  // namespace
}  // namespace radiosity
