// The result file as writeResult writes it collectively: read back exactly (mesh, B, H, rows of
// F, the solve history), whole or not at all, and failures on any rank failing on every rank.
// Runs on one rank and on N with `mpirun -n N build/tests/io_result_write_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "io/store/result.h"
#include "measure/light_error.h"
#include "mpi_environment.h"
#include "result_fixture.h"
#include "temp_dir.h"
#include "text_occurrences.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::attributesWithHistory;
using testing::distribute;
using testing::expectRoundTrip;
using testing::expectSameAttributes;
using testing::namesIn;
using testing::Owned;
using testing::readText;
using testing::ResultFileTest;
using testing::someAttributes;
using testing::strip;
using testing::worldRank;
using testing::worldSize;
using testing::writeText;

// The error measure (measure/light_error.h) on numbers worked by hand, each rank holding a share
// of the patches: emitters that do not reflect are left out, so are patches no light reaches
// (value and error 0), near-black patches count against the floor, and the result is the same
// at any scale of the values and the areas.
TEST(LightError, IsTheRmsOverReflectingPatchesOfEachErrorRelativeToItsOwnValue) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  // Patch: area, ρ, B, error. The mean B over the reflecting patches light reaches (areas 1, 1)
  // is (1 + 3)/2 = 2, so the floor is 0.02.
  struct Patch {
    double area, rho, value, error;
  };
  const std::vector<Patch> all = {{1, 0.5, 1, 0.1},     // 10 %
                                  {1, 0.5, 3, 0.6},     // 20 %
                                  {2, 0.5, 0, 0.0005},  // 0.0005 / floor 0.02 = 2.5 %
                                  {1000, 0.5, 0, 0},    // unlit, no error: left out
                                  {5, 0.0, 100, 50}};   // an emitter that does not reflect
  const double expected = std::sqrt((0.1 * 0.1 + 0.2 * 0.2 + 2 * 0.025 * 0.025) / 4);
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
    EXPECT_NEAR(reflectingMean(MPI_COMM_WORLD, area, rho, value)[0], 2 * scale, 1e-12 * scale);
  }
}

TEST_F(ResultFileTest, RoundTripIsExactAndLeavesOnlyTheFile) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh);
  const ResultAttributes attributes = someAttributes();
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, attributes);
  expectRoundTrip(path, mesh, owned, attributes);
  EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"result.h5", "result.xmf"}));
}

TEST_F(ResultFileTest, RankWithoutPatchesStillTakesPart) {
  const Mesh mesh = strip();
  const Owned owned = distribute(mesh, /*firstRankIdle=*/true);
  const fs::path path = dir_ / "result.h5";
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes());
  expectRoundTrip(path, mesh, owned, someAttributes());
}

/// A made-up global F: row i holds columns i+1 and i+3 (mod np), values from i.
SparseRows someFormFactors(int64_t np) {
  SparseRows f;
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
SparseRows rowsOf(const SparseRows& global, int64_t first, int64_t end) {
  SparseRows local;
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
  const SparseRows global = someFormFactors(mesh.triangleCount());
  const SparseRows mine =
      rowsOf(global, owned.local.firstPatch,
             owned.local.firstPatch + static_cast<int64_t>(owned.local.radiosity.size()));
  FormFactorOutput output{
      {3, 0, static_cast<int64_t>(mesh.triangleCount()) - 3}, {0, 0.5, 1}, nullptr, {}};
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
  EXPECT_TRUE(r.groups.empty());
  // View factors between labels, every rank holding them, rank 0 writing them.
  output.groups = {{"floor", "wall é"}, {2.5, 1e-30}, {0, 0.25, 0.5, 0},
                   {0, 1e-3, 2e-3, 0},  {},           {}};
  writeResult(MPI_COMM_WORLD, path.string(), mesh, owned.local, someAttributes(), output);
  const Result withGroups = readResult(path.string());
  EXPECT_EQ(withGroups.groups.names, output.groups.names);
  EXPECT_EQ(withGroups.groups.area, output.groups.area);
  EXPECT_EQ(withGroups.groups.factors, output.groups.factors);
  EXPECT_EQ(withGroups.groups.factorError, output.groups.factorError);
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
  const SparseRows global = someFormFactors(mesh.triangleCount());
  SparseRows mine =
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
  EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"result.h5", "result.xmf"}));

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
        "solver_choice =\n      gmres: ρ max 0.9 > 0.85"})
    EXPECT_NE(text.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << text;
  // Each figure once: the summary does not repeat the attributes' solver choice and figures.
  const auto count = [&](const std::string& what) { return testing::occurrences(text, what); };
  EXPECT_EQ(count("0.015625"), 1) << text;
  EXPECT_EQ(count("ρ max 0.9 > 0.85"), 1) << text;
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
  EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"result.h5", "result.xmf"}));
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

}  // namespace
}  // namespace radiosity
