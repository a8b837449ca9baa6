// What the HDF5 scene file's tests (io_scene_file_test.cpp, io_scene_file_refusal_test.cpp)
// share: a fresh folder on every rank, scene files written from every rank and damaged copies
// made with serial HDF5 on rank 0, the bit-for-bit comparison of meshes, and a scene of odd
// materials.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "hdf5_rewrite.h"
#include "io/store/scene_file.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity::testing {

class SceneFileTest : public ::testing::Test {
 protected:
  SceneFileTest() : temp_("io_scene_file_test"), dir_(temp_.path()) {}

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Writes `mesh` as `name` from every rank; returns the path.
  std::string write(const std::string& name, const Mesh& mesh) {
    const std::string file = path(name);
    writeSceneFile(MPI_COMM_WORLD, file, mesh, {"test", {{"radiosity", "test"}}});
    return file;
  }

  /// Copies `from` to `to` and applies `damage` to the copy with serial HDF5, on rank 0; every
  /// rank waits for it. Returns the copy's path.
  std::string damaged(const std::string& from, const std::string& to,
                      const std::function<void(hid_t)>& damage) {
    if (worldRank() == 0) {
      std::filesystem::copy_file(from, path(to), std::filesystem::copy_options::overwrite_existing);
      const hid_t file = H5Fopen(path(to).c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      EXPECT_GE(file, 0);
      damage(file);
      EXPECT_GE(H5Fclose(file), 0);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return path(to);
  }

  testing::SharedTempDir temp_;
  std::filesystem::path dir_;
};

/// Every field the format keeps, bit for bit.
inline void expectSameBits(const Mesh& a, const Mesh& b) {
  auto same = [](const auto& x, const auto& y, const char* what) {
    ASSERT_EQ(x.size(), y.size()) << what;
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])), 0) << what;
  };
  same(a.vertices, b.vertices, "vertices");
  same(a.triangles, b.triangles, "triangles");
  same(a.sourceFace, b.sourceFace, "source faces");
  same(a.reflectance, b.reflectance, "reflectance");
  same(a.emission, b.emission, "emission");
  same(a.label, b.label, "labels");
  EXPECT_EQ(a.labelNames, b.labelNames);
  EXPECT_EQ(a.lengthUnit, b.lengthUnit);
}

/// A strip of triangles with a material of its own each, in odd values: -0, the smallest
/// subnormal, 1, huge emission; no labels, no length unit, source faces out of order.
inline Mesh oddMaterials() {
  Mesh mesh;
  for (int i = 0; i < 9; ++i) {
    mesh.vertices.push_back({0.5 * i, 0, 0.1 * i * i});
    mesh.vertices.push_back({0.5 * i, 1.0 + 0.25 * i, 1.0 / 3});
  }
  for (int t = 0; t < 16; ++t) {
    const int64_t i = 2 * (t / 2);
    mesh.triangles.push_back(t % 2 == 0 ? Triangle{i, i + 2, i + 1}
                                        : Triangle{i + 1, i + 2, i + 3});
    mesh.sourceFace.push_back(1000 - 7 * t);
    mesh.reflectance.push_back({t % 3 == 0 ? -0.0 : 0.0, 5e-324 * t, t == 5 ? 1.0 : 0.1 * t / 3});
    mesh.emission.push_back({t == 2 ? 1e100 : 0.0, -0.0, 1.0 / (t + 1)});
  }
  return mesh;
}

/// A damage for SceneFileTest::damaged: dataset `name` rewritten whole with `change` applied to
/// its values (as T).
template <class T>
std::function<void(hid_t)> rewritten(const char* name, hid_t memoryType,
                                     std::function<void(std::vector<T>&)> change) {
  return [=](hid_t f) { rewriteDataset<T>(f, name, memoryType, change); };
}

}  // namespace radiosity::testing
