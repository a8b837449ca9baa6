// Reading result files: missing, foreign or damaged files named in an InputError, the optional
// /patches/radiosity_stderr dataset, and the description `radiosity info` prints. Runs on one
// rank and on N with `mpirun -n N build/tests/io_result_read_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "expect_error.h"
#include "io/store/result.h"
#include "measure/light_error.h"
#include "mpi_environment.h"
#include "result_fixture.h"
#include "temp_dir.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::attributesWithHistory;
using testing::distribute;
using testing::expectRoundTrip;
using testing::namesIn;
using testing::Owned;
using testing::radiosityOf;
using testing::readText;
using testing::ResultFileTest;
using testing::someAttributes;
using testing::strip;
using testing::worldRank;
using testing::worldSize;
using testing::writeText;

using testing::expectInputError;

TEST_F(ResultFileTest, ReadingAMissingFileNamesIt) {
  const std::string path = (dir_ / "absent.h5").string();
  expectInputError([&] { readResult(path); }, {path, "no such file"});
  expectInputError([&] { describeResult(path); }, {path});
}

TEST_F(ResultFileTest, ReadingATextFileNamesIt) {
  const fs::path path = dir_ / "words.h5";
  if (worldRank() == 0) writeText(path, "not HDF5 at all\n");
  MPI_Barrier(MPI_COMM_WORLD);
  expectInputError([&] { readResult(path.string()); }, {path.string(), "not an HDF5 file"});
  expectInputError([&] { describeResult(path.string()); }, {path.string()});
}

// A copy of `good` named `name` beside it, opened with serial HDF5 and given to `damage`. On one
// rank (serial HDF5).
fs::path damagedCopy(const fs::path& good, const std::string& name,
                     const std::function<void(hid_t)>& damage) {
  const fs::path copy = good.parent_path() / name;
  fs::copy_file(good, copy);
  const hid_t file = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  EXPECT_GE(file, 0) << copy;
  damage(file);
  H5Fclose(file);
  return copy;
}

TEST_F(ResultFileTest, MissingOrMisshapenDatasetIsNamed) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const fs::path good = dir_ / "good.h5";
  writeResult(MPI_COMM_WORLD, good.string(), mesh, owned.local, someAttributes());
  // Damaged copies are made and read on rank 0 only, with serial HDF5.
  if (worldRank() == 0) {
    const fs::path missing = damagedCopy(good, "missing.h5", [](hid_t file) {
      EXPECT_GE(H5Ldelete(file, "/patches/irradiance", H5P_DEFAULT), 0);
    });
    const fs::path misshapen = damagedCopy(good, "misshapen.h5", [](hid_t file) {
      EXPECT_GE(H5Ldelete(file, "/patches/area", H5P_DEFAULT), 0);
      const hsize_t dims[2] = {10, 2};
      const hid_t space = H5Screate_simple(2, dims, nullptr);
      const hid_t dataset = H5Dcreate2(file, "/patches/area", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                       H5P_DEFAULT, H5P_DEFAULT);
      EXPECT_GE(dataset, 0);
      H5Dclose(dataset);
      H5Sclose(space);
    });
    expectInputError([&] { readResult(missing.string()); },
                     {missing.string(), "/patches/irradiance"});
    expectInputError([&] { describeResult(missing.string()); },
                     {missing.string(), "/patches/irradiance"});
    expectInputError([&] { readResult(misshapen.string()); },
                     {misshapen.string(), "/patches/area", "[10, 2]", "expected [10]"});
  }
}

TEST_F(ResultFileTest, DamagedHistoryIsNamed) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, attributesWithHistory());
  if (worldRank() == 0) {
    // Row 1 gets channel 1.5, which is no channel.
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t dataset = H5Dopen2(file, "/solve/history", H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    std::vector<double> rows(6 * 4);
    ASSERT_GE(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), 0);
    rows[4] = 1.5;
    ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), 0);
    H5Dclose(dataset);
    H5Fclose(file);
    expectInputError([&] { readResult(path.string()); },
                     {path.string(), "/solve/history", "row 1", "channel 1.5"});
  }
}

TEST_F(ResultFileTest, DamagedGroupsAreNamed) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  FormFactorOutput output;
  output.groups = {{"ground", "building 1"}, {3, 1}, {0, 0.1, 0.3, 0}, {}, {}, {}};
  const fs::path good = dir_ / "good.h5";
  writeResult(MPI_COMM_WORLD, good.string(), mesh, owned.local, someAttributes(), output);
  if (worldRank() == 0) {
    const fs::path noArea = damagedCopy(good, "no_area.h5", [](hid_t file) {
      EXPECT_GE(H5Ldelete(file, "/groups/area", H5P_DEFAULT), 0);
    });
    // The names attribute replaced by one that names a single group.
    const fs::path oneName = damagedCopy(good, "one_name.h5", [](hid_t file) {
      const hid_t dataset = H5Dopen2(file, "/groups/view_factors", H5P_DEFAULT);
      EXPECT_GE(dataset, 0);
      EXPECT_GE(H5Adelete(dataset, "names"), 0);
      const hid_t type = H5Tcopy(H5T_C_S1);
      H5Tset_size(type, 6);
      const hsize_t one = 1;
      const hid_t space = H5Screate_simple(1, &one, nullptr);
      const hid_t attribute = H5Acreate2(dataset, "names", type, space, H5P_DEFAULT, H5P_DEFAULT);
      EXPECT_GE(attribute, 0);
      EXPECT_GE(H5Awrite(attribute, type, "ground"), 0);
      H5Aclose(attribute);
      H5Sclose(space);
      H5Tclose(type);
      H5Dclose(dataset);
    });
    expectInputError([&] { readResult(noArea.string()); }, {noArea.string(), "/groups/area"});
    expectInputError([&] { readResult(oneName.string()); },
                     {oneName.string(), "names", "1 names for 2 groups"});
    EXPECT_EQ(readResult(good.string()).groups.names, output.groups.names);
  }
}

/// A made-up standard error of B: every bit of a double in R, the smallest subnormal and 0 in G,
/// and in B a value that, against B = 1e308, squares beyond the double range.
std::vector<Rgb> stderrOf(const Mesh& mesh) {
  std::vector<Rgb> e;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    e.push_back({(t + 1) / 3.0, t % 2 == 0 ? 5e-324 : 0.0, 1e300});
  return e;
}

/// `owned` with its rows of stderrOf(mesh).
Owned withStderr(const Mesh& mesh, Owned owned) {
  const std::vector<Rgb> e = stderrOf(mesh);
  const auto first = e.begin() + owned.local.firstPatch;
  owned.local.radiosityStderr.assign(first, first + owned.local.radiosity.size());
  return owned;
}

/// Whether `path` holds the dataset /patches/radiosity_stderr (serial HDF5, any rank).
bool hasStderrDataset(const fs::path& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(file, 0);
  const bool found = H5Lexists(file, "/patches/radiosity_stderr", H5P_DEFAULT) > 0;
  H5Fclose(file);
  return found;
}

std::string formatted(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%14.6g", value);
  return text;
}

TEST_F(ResultFileTest, RadiosityStderrRoundTripsExactlyFromEveryRanksSlab) {
  const Mesh mesh = strip();
  for (bool firstRankIdle : {false, true}) {
    SCOPED_TRACE(firstRankIdle ? "rank 0 owns no patch" : "every rank owns patches");
    const Owned owned = withStderr(mesh, distribute(mesh, firstRankIdle));
    const fs::path path = dir_ / "result.h5";
    writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
    expectRoundTrip(path, mesh, owned, someAttributes());
    const Result r = readResult(path.string());
    EXPECT_EQ(r.radiosityStderr, stderrOf(mesh));
    EXPECT_TRUE(hasStderrDataset(path));
    EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"result.h5", "result.xmf"}));

    // The summary: the estimate in the measure of measure/light_error.h (checked there by hand).
    const std::vector<Rgb> b = radiosityOf(mesh), e = stderrOf(mesh);
    std::vector<double> area;
    for (int64_t t = 0; t < mesh.triangleCount(); ++t) area.push_back(mesh.area(t));
    const auto relative = relativeLightError(MPI_COMM_SELF, area, mesh.reflectance, b, e);
    std::string line = "estimated sampling error    ";
    for (int k = 0; k < 3; ++k) line += formatted(relative[k]);
    line += "\n";
    const std::string text = describeResult(path.string());
    for (const std::string& expected : {std::string("/patches/radiosity_stderr float64  [10, 3]"),
                                        line, std::string("relative to its own B")})
      EXPECT_NE(text.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << text;
  }
}

TEST_F(ResultFileTest, ResultWithoutRadiosityStderrHasNoDataset) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh, /*firstRankIdle=*/true);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  EXPECT_TRUE(readResult(path.string()).radiosityStderr.empty());
  EXPECT_FALSE(hasStderrDataset(path));
  const std::string text = describeResult(path.string());
  EXPECT_EQ(text.find("stderr"), std::string::npos) << text;
  EXPECT_EQ(text.find("sampling error"), std::string::npos) << text;
}

/// writeResult must fail on every rank with exit code 1 and a message holding `mention`, leaving
/// the file that was there untouched and no other.
void expectCollectiveFailure(const fs::path& dir, const Mesh& mesh, const LocalSolution& local,
                             const std::string& mention) {
  const fs::path path = dir / "result.h5";
  if (worldRank() == 0) writeText(path, "precious\n");
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    writeResult(MPI_COMM_WORLD, path.string(), mesh, local, someAttributes());
    ADD_FAILURE() << "writeResult did not throw";
  } catch (const InputError& e) {
    ADD_FAILURE() << "not an input error: " << e.what();
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(readText(path), "precious\n");
  EXPECT_EQ(namesIn(dir), std::set<std::string>{"result.h5"});
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST_F(ResultFileTest, RadiosityStderrWithTheWrongRowCountFailsEverywhere) {
  const Mesh mesh = strip();
  const int last = worldSize() - 1;
  // One row short on the last rank only.
  Owned owned = withStderr(mesh, distribute(mesh));
  if (worldRank() == last) owned.local.radiosityStderr.pop_back();
  expectCollectiveFailure(dir_, mesh, owned.local, "radiosity stderr has");
  // One row too many on the last rank only.
  owned = withStderr(mesh, distribute(mesh));
  if (worldRank() == last) owned.local.radiosityStderr.push_back({1, 1, 1});
  expectCollectiveFailure(dir_, mesh, owned.local, "radiosity stderr has");
  // Only the last rank has any (with several ranks, the others own patches but give none).
  if (worldSize() > 1) {
    owned = distribute(mesh);
    if (worldRank() == last) owned = withStderr(mesh, owned);
    expectCollectiveFailure(dir_, mesh, owned.local, "radiosity stderr has 0 rows");
  }
}

TEST_F(ResultFileTest, NegativeOrNonFiniteRadiosityStderrFailsEverywhere) {
  const Mesh mesh = strip();
  const int last = worldSize() - 1;
  for (double bad : {-1.0, -5e-324, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    SCOPED_TRACE(bad);
    Owned owned = withStderr(mesh, distribute(mesh));
    if (worldRank() == last) owned.local.radiosityStderr.back()[1] = bad;
    expectCollectiveFailure(dir_, mesh, owned.local, "radiosity stderr of patch 9 channel 1");
  }
  // -0 is ≥ 0, so it is a valid stderr and reads back as written.
  Owned owned = withStderr(mesh, distribute(mesh));
  if (worldRank() == last) owned.local.radiosityStderr.back()[1] = -0.0;
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  EXPECT_EQ(readResult(path.string()).radiosityStderr.back()[1], 0.0);
}

TEST_F(ResultFileTest, DamagedRadiosityStderrIsNamed) {
  const Mesh mesh = strip();
  const Owned owned = withStderr(mesh, distribute(mesh));
  const fs::path good = dir_ / "good.h5";
  writeResult(MPI_COMM_WORLD, good.string(), mesh, owned.local, someAttributes());
  if (worldRank() == 0) {
    const fs::path negative = dir_ / "negative.h5", misshapen = dir_ / "misshapen.h5";
    fs::copy_file(good, negative);
    fs::copy_file(good, misshapen);
    // Row 4, channel 2 becomes -0.5.
    hid_t file = H5Fopen(negative.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    hid_t dataset = H5Dopen2(file, "/patches/radiosity_stderr", H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    std::vector<double> rows(10 * 3);
    ASSERT_GE(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), 0);
    rows[3 * 4 + 2] = -0.5;
    ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), 0);
    H5Dclose(dataset);
    H5Fclose(file);
    // A [9, 3] dataset in its place.
    file = H5Fopen(misshapen.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "/patches/radiosity_stderr", H5P_DEFAULT), 0);
    const hsize_t dims[2] = {9, 3};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    dataset = H5Dcreate2(file, "/patches/radiosity_stderr", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                         H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Fclose(file);
    expectInputError([&] { readResult(negative.string()); },
                     {negative.string(), "/patches/radiosity_stderr", "row 4", "-0.5"});
    expectInputError([&] { describeResult(negative.string()); },
                     {negative.string(), "/patches/radiosity_stderr"});
    expectInputError(
        [&] { readResult(misshapen.string()); },
        {misshapen.string(), "/patches/radiosity_stderr", "[9, 3]", "expected [10, 3]"});
  }
}

TEST_F(ResultFileTest, DescriptionListsDatasetsAttributesAndSummary) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  const std::string text = describeResult(path.string());
  for (const char* expected : {"/mesh/vertices",
                               "float64  [12, 3]",
                               "/mesh/triangles",
                               "int64    [10, 3]",
                               "/patches/area",
                               "float64  [10]",
                               "/patches/normal",
                               "/patches/reflectance",
                               "/patches/emission",
                               "/patches/radiosity",
                               "/patches/irradiance",
                               "/patches/source_face",
                               "int64    [10]",
                               "/patches/rank",
                               "int32    [10]",
                               "format_version = 1",
                               "rays_per_patch = 123456789012",
                               "seed = 18364758544493064720",
                               "solver = \"gmres\"",
                               "iterations = 42",
                               "residual = 3.25e-09",
                               "converged = 1",
                               "scene = \"builtin:cornell?rho=0.5 (größer)\"",
                               "      rays = 1000",
                               "time_solve = 0.125",
                               "time_formfactor = 1.5",
                               "patches: 10",
                               "vertices: 12"})
    EXPECT_NE(text.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << text;
  // Emission: only patch 3 emits, so ΣA·E in R is its area times 10.
  std::ostringstream power;
  power.precision(6);
  power << mesh.area(3) * 10;
  EXPECT_NE(text.find(power.str()), std::string::npos) << text;
}

}  // namespace
}  // namespace radiosity
