// The result file: what writeResult writes collectively, readResult reads back exactly, and the
// file appears whole or not at all. Runs on one rank as a plain executable and on N ranks with
// `mpirun -n N build/tests/io_result_test` (each rank then writes its own block of patches).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/core/error.h"
#include "io/core/matrix_rows.h"
#include "io/core/mesh.h"
#include "io/store/light_error.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;

using testing::worldRank;
using testing::worldSize;

/// A 10-triangle strip bent out of plane, so that areas and normals differ between patches.
Mesh strip() {
  Mesh mesh;
  for (int i = 0; i < 6; ++i) {
    mesh.vertices.push_back({0.5 * i, 0, 0.1 * i * i});
    mesh.vertices.push_back({0.5 * i, 1.0 + 0.25 * i, 0});
  }
  for (int t = 0; t < 10; ++t) {
    const int64_t i = 2 * (t / 2);
    if (t % 2 == 0)
      mesh.triangles.push_back({i, i + 2, i + 1});
    else
      mesh.triangles.push_back({i + 1, i + 2, i + 3});
    mesh.sourceFace.push_back(t / 2);
    mesh.reflectance.push_back({0.1 * (t % 5), 0.5, 1.0});
    mesh.emission.push_back(t == 3 ? Rgb{10, 20.5, 1e-300} : Rgb{0, 0, 0});
  }
  return mesh;
}

std::vector<Rgb> radiosityOf(const Mesh& mesh) {
  std::vector<Rgb> b;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    b.push_back({t + 0.25, 2.0 * t + 1.0 / 3, 1e308});
  return b;
}

std::vector<Rgb> irradianceOf(const Mesh& mesh) {
  std::vector<Rgb> h;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) h.push_back({-0.0, 1.0 / (t + 7), 5e-324});
  return h;
}

ResultAttributes someAttributes() {
  ResultAttributes a;
  a.ranks = worldSize();
  a.raysPerPatch = 123456789012;
  a.seed = 0xFEDCBA9876543210ull;  // above the int64 range
  a.solver = "gmres";
  a.iterations = 42;
  a.residual = 3.25e-9;
  a.converged = true;
  a.scene = "builtin:cornell?rho=0.5 (größer)";
  a.options = "max-area = 0.01\nrays = 1000\n";
  a.stageSeconds = {{"formfactor", 1.5}, {"solve", 0.125}, {"write", 1e-6}};
  return a;
}

/// The first patch of `rank` when the patches are dealt in contiguous blocks; with
/// `firstRankIdle`, rank 0 of several owns none.
int64_t blockStart(int64_t np, int rank, int size, bool firstRankIdle) {
  if (!firstRankIdle || size == 1) return np * rank / size;
  return rank == 0 ? 0 : np * (rank - 1) / (size - 1);
}

struct Owned {
  LocalSolution local;
  std::vector<int32_t> owner;  ///< rank of every patch
};

Owned distribute(const Mesh& mesh, bool firstRankIdle = false) {
  const int64_t np = mesh.triangleCount();
  const int rank = worldRank(), size = worldSize();
  Owned o;
  const int64_t first = blockStart(np, rank, size, firstRankIdle);
  const int64_t end = blockStart(np, rank + 1, size, firstRankIdle);
  const std::vector<Rgb> b = radiosityOf(mesh), h = irradianceOf(mesh);
  o.local.firstPatch = first;
  o.local.radiosity.assign(b.begin() + first, b.begin() + end);
  o.local.irradiance.assign(h.begin() + first, h.begin() + end);
  for (int r = 0; r < size; ++r)
    for (int64_t t = blockStart(np, r, size, firstRankIdle);
         t < blockStart(np, r + 1, size, firstRankIdle); ++t)
      o.owner.push_back(r);
  return o;
}

std::set<std::string> namesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Each test gets a fresh directory, the same on every rank.
class ResultFileTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_FALSE(dir_.empty()); }

  radiosity::testing::SharedTempDir temp_{"io_result_test"};
  fs::path dir_ = temp_.path();
};

void expectSameAttributes(const ResultAttributes& a, const ResultAttributes& b) {
  EXPECT_EQ(a.formatVersion, b.formatVersion);
  EXPECT_EQ(a.ranks, b.ranks);
  EXPECT_EQ(a.raysPerPatch, b.raysPerPatch);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.solver, b.solver);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.residual, b.residual);
  EXPECT_EQ(a.converged, b.converged);
  EXPECT_EQ(a.scene, b.scene);
  EXPECT_EQ(a.options, b.options);
  EXPECT_EQ(a.stageSeconds, b.stageSeconds);
  EXPECT_EQ(a.history.channel, b.history.channel);
  EXPECT_EQ(a.history.iteration, b.history.iteration);
  EXPECT_EQ(a.history.residual, b.history.residual);
  EXPECT_EQ(a.history.seconds, b.history.seconds);
  EXPECT_EQ(a.solveFigures, b.solveFigures);
  EXPECT_EQ(a.solverChoice, b.solverChoice);
}

void expectRoundTrip(const fs::path& path, const Mesh& mesh, const Owned& owned,
                     const ResultAttributes& attributes) {
  const Result r = readResult(path.string());
  EXPECT_EQ(r.mesh.vertices, mesh.vertices);
  EXPECT_EQ(r.mesh.triangles, mesh.triangles);
  EXPECT_EQ(r.mesh.sourceFace, mesh.sourceFace);
  EXPECT_EQ(r.mesh.reflectance, mesh.reflectance);
  EXPECT_EQ(r.mesh.emission, mesh.emission);
  ASSERT_EQ(r.area.size(), mesh.triangles.size());
  ASSERT_EQ(r.normal.size(), mesh.triangles.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_EQ(r.area[t], mesh.area(t)) << "patch " << t;
    EXPECT_EQ(r.normal[t], mesh.normal(t)) << "patch " << t;
  }
  EXPECT_EQ(r.radiosity, radiosityOf(mesh));
  EXPECT_EQ(r.irradiance, irradianceOf(mesh));
  EXPECT_EQ(r.rank, owned.owner);
  expectSameAttributes(r.attributes, attributes);
}

// The error measure (io/store/light_error.h) on numbers worked by hand, each rank holding a share of
// the patches: emitters that do not reflect are left out, near-black patches count against the
// floor, and the result is the same at any scale of the values and the areas.
TEST(LightError, IsTheRmsOverReflectingPatchesOfEachErrorRelativeToItsOwnValue) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  // Patch: area, ρ, B, error. The mean B over reflecting patches (areas 1, 1, 2) is
  // (1 + 3 + 2·0)/4 = 1, so the floor is 0.01.
  struct Patch {
    double area, rho, value, error;
  };
  const std::vector<Patch> all = {{1, 0.5, 1, 0.1},      // 10 %
                                  {1, 0.5, 3, 0.6},      // 20 %
                                  {2, 0.5, 0, 0.0005},   // 0.0005 / floor 0.01 = 5 %
                                  {5, 0.0, 100, 50}};    // an emitter that does not reflect
  const double expected = std::sqrt((0.1 * 0.1 + 0.2 * 0.2 + 2 * 0.05 * 0.05) / 4);
  for (double scale : {1.0, 1e-150, 1e150}) {
    std::vector<double> area;
    std::vector<Rgb> rho, value, error;
    for (size_t i = 0; i < all.size(); ++i) {
      if (static_cast<int>(i) % ranks != rank) continue;
      area.push_back(all[i].area * scale);
      rho.push_back({all[i].rho, all[i].rho, 0.0});
      value.push_back({all[i].value * scale, all[i].value, all[i].value});
      error.push_back({all[i].error * scale, all[i].error, all[i].error});
    }
    const auto rms = relativeLightError(MPI_COMM_WORLD, area, rho, value, error);
    EXPECT_NEAR(rms[0], expected, 1e-12) << scale;
    EXPECT_NEAR(rms[1], expected, 1e-12) << scale;
    EXPECT_EQ(rms[2], 0.0);  // nothing reflects in blue
    EXPECT_NEAR(reflectingMean(MPI_COMM_WORLD, area, rho, value)[0], scale, 1e-12 * scale);
  }
}

TEST_F(ResultFileTest, RoundTripIsExactAndLeavesOnlyTheFile) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const ResultAttributes attributes = someAttributes();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, attributes);
  expectRoundTrip(path, mesh, owned, attributes);
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});
}

TEST_F(ResultFileTest, RankWithoutPatchesStillTakesPart) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh, /*firstRankIdle=*/true);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  expectRoundTrip(path, mesh, owned, someAttributes());
}

/// A made-up global F: row i holds columns i+1 and i+3 (mod np), values from i.
MatrixRows someFormFactors(int64_t np) {
  MatrixRows f;
  for (int64_t i = 0; i < np; ++i) {
    for (int64_t k : {1, 3}) {
      f.column.push_back((i + k) % np);
      f.value.push_back(0.125 * static_cast<double>(i) + 1.0 / static_cast<double>(k));
    }
    f.rowStart.push_back(f.nonzeros());
  }
  return f;
}

/// Rows [first, end) of `global`.
MatrixRows rowsOf(const MatrixRows& global, int64_t first, int64_t end) {
  MatrixRows local;
  local.firstRow = first;
  const int64_t begin = global.rowStart[first];
  for (int64_t i = first; i < end; ++i) local.rowStart.push_back(global.rowStart[i + 1] - begin);
  local.column.assign(global.column.begin() + begin, global.column.begin() + global.rowStart[end]);
  local.value.assign(global.value.begin() + begin, global.value.begin() + global.rowStart[end]);
  return local;
}

TEST_F(ResultFileTest, FormFactorRowsAndHistogramRoundTripFromEveryRanksSlab) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh, /*firstRankIdle=*/true);
  const MatrixRows global = someFormFactors(mesh.triangleCount());
  const MatrixRows mine =
      rowsOf(global, owned.local.firstPatch,
             owned.local.firstPatch + static_cast<int64_t>(owned.local.radiosity.size()));
  FormFactorOutput output{{3, 0, static_cast<int64_t>(mesh.triangleCount()) - 3}, {0, 0.5, 1}};
  output.rows = &mine;
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes(), output);
  const Result r = readResult(path.string());
  EXPECT_EQ(r.rowSumHistogram, output.rowSumHistogram);
  EXPECT_EQ(r.rowSumBinEdges, output.rowSumBinEdges);
  ASSERT_TRUE(r.formFactors.has_value());
  EXPECT_EQ(r.formFactors->firstRow, 0);
  EXPECT_EQ(r.formFactors->rowStart, global.rowStart);
  EXPECT_EQ(r.formFactors->column, global.column);
  EXPECT_EQ(r.formFactors->value, global.value);
  // Without rows of F only the histogram is written; without either, no /formfactors at all.
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes(), {{1, 2}, {0, 1}});
  EXPECT_FALSE(readResult(path.string()).formFactors.has_value());
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  EXPECT_TRUE(readResult(path.string()).rowSumHistogram.empty());
  EXPECT_EQ(describeResult(path.string()).find("/formfactors"), std::string::npos);
}

TEST_F(ResultFileTest, FormFactorRowsNotMatchingThePatchesFailEverywhere) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const MatrixRows global = someFormFactors(mesh.triangleCount());
  MatrixRows mine =
      rowsOf(global, owned.local.firstPatch,
             owned.local.firstPatch + static_cast<int64_t>(owned.local.radiosity.size()));
  if (worldRank() == 0) mine.column.push_back(0);  // one column too many for the row starts
  FormFactorOutput output;
  output.rows = &mine;
  const fs::path path = dir_ / "result.h5";
  try {
    writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes(), output);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("CSR"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

/// A history of three channels, values chosen to need every bit of a double.
ResultAttributes attributesWithHistory() {
  ResultAttributes a = someAttributes();
  a.history.channel = {0, 0, 0, 1, 1, 2};
  a.history.iteration = {0, 1, 2, 0, 1, int64_t{1} << 53};
  a.history.residual = {1.0, 1.0 / 3, 5e-324, 0.1, 2.5e-10, 1e308};
  a.history.seconds = {0.0, 1e-6, 0.1 + 0.2, 0.5, 0.75, 12345.678901234567};
  a.solveFigures = {{"setup_seconds", 0.015625}, {"spectral_radius", 0.9 / 7}, {"", -0.0}};
  a.solverChoice = "gmres: ρ max 0.9 > 0.85\nsecond line";
  return a;
}

TEST_F(ResultFileTest, SolveHistoryFiguresAndChoiceRoundTripExactly) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  ResultAttributes attributes = attributesWithHistory();
  // Only rank 0's history and figures are written: the others hold something else.
  ResultAttributes mine = attributes;
  if (worldRank() != 0) {
    mine.history = SolveHistory{};
    mine.history.channel = {2};
    mine.history.iteration = {7};
    mine.history.residual = {0.5};
    mine.history.seconds = {1};
    mine.solveFigures = {{"other", 1}};
    mine.solverChoice = "other";
  }
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, mine);
  expectRoundTrip(path, mesh, owned, attributes);
  EXPECT_EQ(readResult(path.string()).attributes.history.size(), 6u);
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});

  if (worldRank() == 0) {
    // The dataset is float64 [6, 4] and its attribute `columns` names the columns.
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t dataset = H5Dopen2(file, "/solve/history", H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    const hid_t space = H5Dget_space(dataset);
    hsize_t dims[2] = {};
    EXPECT_EQ(H5Sget_simple_extent_ndims(space), 2);
    H5Sget_simple_extent_dims(space, dims, nullptr);
    EXPECT_EQ(dims[0], 6u);
    EXPECT_EQ(dims[1], 4u);
    const hid_t attribute = H5Aopen(dataset, "columns", H5P_DEFAULT);
    ASSERT_GE(attribute, 0);
    const hid_t type = H5Aget_type(attribute);
    const size_t width = H5Tget_size(type);
    std::string names(4 * width, '\0');
    EXPECT_GE(H5Aread(attribute, type, names.data()), 0);
    std::vector<std::string> columns;
    for (int k = 0; k < 4; ++k) columns.push_back(names.substr(k * width, width).c_str());
    EXPECT_EQ(columns, (std::vector<std::string>{"channel", "iteration", "residual", "seconds"}));
    H5Tclose(type);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Dclose(dataset);
    H5Fclose(file);
  }

  const std::string text = describeResult(path.string());
  for (const char* expected :
       {"/solve/history", "float64  [6, 4]", "solver_choice =", "solve_setup_seconds = 0.015625",
        "solve history: 6 entries", "red: last iteration 2, residual 5e-324",
        "green: last iteration 1, residual 2.5e-10", "blue: last iteration 9007199254740992",
        "solve figures:", "solver choice: gmres: ρ max 0.9 > 0.85"})
    EXPECT_NE(text.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << text;
}

TEST_F(ResultFileTest, ResultWithoutHistoryReadsBackEmpty) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  const Result r = readResult(path.string());
  EXPECT_EQ(r.attributes.history.size(), 0u);
  EXPECT_TRUE(r.attributes.history.channel.empty());
  EXPECT_TRUE(r.attributes.history.iteration.empty());
  EXPECT_TRUE(r.attributes.history.seconds.empty());
  EXPECT_TRUE(r.attributes.solveFigures.empty());
  EXPECT_TRUE(r.attributes.solverChoice.empty());
  const std::string text = describeResult(path.string());
  EXPECT_EQ(text.find("/solve"), std::string::npos) << text;
  EXPECT_EQ(text.find("solver_choice"), std::string::npos) << text;
  EXPECT_EQ(text.find("solve history"), std::string::npos) << text;
}

TEST_F(ResultFileTest, InconsistentHistoryFailsEverywhereAndKeepsTheOldFile) {
  const fs::path path = dir_ / "result.h5";
  if (worldRank() == 0) writeText(path, "precious\n");
  MPI_Barrier(MPI_COMM_WORLD);
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  ResultAttributes attributes = attributesWithHistory();
  attributes.history.seconds.pop_back();
  try {
    writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, attributes);
    ADD_FAILURE() << "writeResult did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find("solve history"), std::string::npos) << e.what();
  }
  attributes = attributesWithHistory();
  attributes.history.channel[1] = 3;
  EXPECT_THROW(writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, attributes), Error);
  EXPECT_EQ(readText(path), "precious\n");
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});
}

TEST_F(ResultFileTest, EmptyMeshRoundTrip) {
  const fs::path path = dir_ / "empty.h5";
  ResultAttributes attributes;  // defaults: empty strings, no stages
  writeResult(MPI_COMM_WORLD, path.string(), Mesh{}, LocalSolution{}, attributes);
  const Result r = readResult(path.string());
  EXPECT_TRUE(r.mesh.vertices.empty());
  EXPECT_TRUE(r.mesh.triangles.empty());
  EXPECT_TRUE(r.radiosity.empty());
  EXPECT_TRUE(r.rank.empty());
  expectSameAttributes(r.attributes, attributes);
}

TEST_F(ResultFileTest, ReplacesAnExistingFile) {
  const fs::path path = dir_ / "result.h5";
  if (worldRank() == 0) writeText(path, "an older result\n");
  MPI_Barrier(MPI_COMM_WORLD);
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  expectRoundTrip(path, mesh, owned, someAttributes());
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});
}

TEST_F(ResultFileTest, MissingDirectoryFailsOnEveryRankAndLeavesNothing) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const std::string path = (dir_ / "no-such-directory" / "result.h5").string();
  try {
    writeResult(MPI_COMM_WORLD, path, mesh, owned.local, someAttributes());
    ADD_FAILURE() << "writeResult did not throw";
  } catch (const InputError& e) {
    ADD_FAILURE() << "not an input error: " << e.what();
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(namesIn(dir_).empty());
}

TEST_F(ResultFileTest, BadArgumentsOnOneRankFailEverywhereAndKeepTheOldFile) {
  const fs::path path = dir_ / "result.h5";
  if (worldRank() == 0) writeText(path, "precious\n");
  MPI_Barrier(MPI_COMM_WORLD);
  const Mesh mesh = strip();
  Owned owned = distribute(mesh);
  // Only the last rank is wrong; every rank must throw rather than wait for it.
  if (worldRank() == worldSize() - 1) owned.local.irradiance.pop_back();
  EXPECT_THROW(writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes()),
               Error);
  EXPECT_EQ(readText(path), "precious\n");
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});
}

TEST_F(ResultFileTest, PatchesNotCoveredFailEverywhere) {
  const Mesh mesh = strip();
  Owned owned = distribute(mesh);
  if (worldRank() == worldSize() - 1) owned.local.radiosity.pop_back();
  if (worldRank() == worldSize() - 1) owned.local.irradiance.pop_back();
  try {
    writeResult(MPI_COMM_WORLD, (dir_ / "result.h5").string(), mesh, owned.local, someAttributes());
    ADD_FAILURE() << "writeResult did not throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("9 patches of 10"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(namesIn(dir_).empty());
}

TEST_F(ResultFileTest, FailedRenameRemovesTheTemporaryAndKeepsTheTarget) {
  // A non-empty directory under the name: the file is written, but cannot replace it.
  const fs::path path = dir_ / "result.h5";
  if (worldRank() == 0) {
    fs::create_directory(path);
    writeText(path / "keep", "x");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  try {
    writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
    ADD_FAILURE() << "writeResult did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find("rename"), std::string::npos) << e.what();
  }
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});
  EXPECT_EQ(namesIn(path), std::set<std::string>{"keep"});
}

template <class Call>
void expectInputError(Call call, const std::vector<std::string>& mentions) {
  try {
    call();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
    for (const std::string& word : mentions)
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos)
          << "'" << word << "' not in: " << e.what();
  }
}

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

TEST_F(ResultFileTest, MissingOrMisshapenDatasetIsNamed) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const fs::path good = dir_ / "good.h5";
  writeResult(MPI_COMM_WORLD, good.string(), mesh, owned.local, someAttributes());
  // Damaged copies are made and read on rank 0 only, with serial HDF5.
  if (worldRank() == 0) {
    const fs::path missing = dir_ / "missing.h5", misshapen = dir_ / "misshapen.h5";
    fs::copy_file(good, missing);
    fs::copy_file(good, misshapen);
    hid_t file = H5Fopen(missing.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "/patches/irradiance", H5P_DEFAULT), 0);
    H5Fclose(file);
    file = H5Fopen(misshapen.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "/patches/area", H5P_DEFAULT), 0);
    const hsize_t dims[2] = {10, 2};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t dataset = H5Dcreate2(file, "/patches/area", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                     H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Fclose(file);
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
    EXPECT_EQ(namesIn(dir_), std::set<std::string>{"result.h5"});

    // The summary: the estimate in the measure of io/store/light_error.h (checked there by hand).
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
