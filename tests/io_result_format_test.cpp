// The result format's names (io/store/result_format.h) against what the writer writes: a result
// with everything in it holds exactly the named groups, datasets and attributes, each dataset
// labelled; and the check both collective writers make that the ranks' blocks tile the rows.
// Runs on one rank and on N with `mpirun -n N build/tests/io_result_format_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <array>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "io/store/rank_blocks.h"
#include "io/store/result.h"
#include "io/store/result_format.h"
#include "mpi_environment.h"
#include "result_fixture.h"

namespace radiosity {
namespace {

namespace format = result_format;
namespace attribute = result_format::attribute;
using testing::attributesWithHistory;
using testing::distribute;
using testing::Owned;
using testing::ResultFileTest;
using testing::strip;

/// Every group and dataset of the file (full names), and whether each is a dataset.
struct Objects {
  std::set<std::string> groups, datasets;
};

Objects objectsIn(hid_t file) {
  std::vector<std::string> links;
  auto collect = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
    return 0;
  };
  EXPECT_GE(H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, collect, &links), 0);
  Objects objects;
  for (const std::string& link : links) {
    H5O_info_t info;
    EXPECT_GE(H5Oget_info_by_name2(file, link.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT), 0);
    if (info.type == H5O_TYPE_GROUP) objects.groups.insert(link);
    if (info.type == H5O_TYPE_DATASET) objects.datasets.insert(link);
  }
  return objects;
}

std::set<std::string> attributesOf(hid_t object) {
  std::set<std::string> names;
  auto collect = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
    static_cast<std::set<std::string>*>(data)->insert(name);
    return 0;
  };
  EXPECT_GE(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), 0);
  return names;
}

std::set<std::string> attributesOf(hid_t file, const std::string& dataset) {
  const hid_t id = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  EXPECT_GE(id, 0) << dataset;
  std::set<std::string> names = attributesOf(id);
  H5Dclose(id);
  return names;
}

/// The strip with every optional part: labels, error estimates, a hidden patch, rows of F with
/// their histogram, view factors between the labels, a history, a length unit.
TEST_F(ResultFileTest, AFullResultHoldsExactlyTheNamedGroupsDatasetsAndAttributes) {
  Mesh mesh = strip();
  mesh.labelNames = {"floor", "wall"};
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) mesh.label.push_back(t % 2);
  Owned owned = distribute(mesh);
  const size_t mine = owned.local.radiosity.size();
  owned.local.radiosityStderr.assign(mine, Rgb{0.5, 0.25, 0});
  owned.local.radiosityDiscretisation.assign(mine, Rgb{-0.5, 0, 0.125});
  owned.local.hidden.assign(mine, 0);
  if (owned.local.firstPatch == 0 && mine > 0) owned.local.hidden[0] = 1;
  SparseRows rows;
  rows.firstRow = owned.local.firstPatch;
  rows.rowStart.assign(mine + 1, 0);  // no nonzeros: the datasets are there all the same
  FormFactorOutput output{
      {1, 2},
      {0, 0.5},
      &rows,
      {{"floor", "wall"}, {1, 2}, {0, 0.5, 0.25, 0}, {0, 1e-3, 1e-3, 0}, {}, {}}};
  ResultAttributes attributes = attributesWithHistory();
  attributes.lengthUnit = "m";
  const std::string path = (dir_ / "result.h5").string();
  writeResult(MPI_COMM_WORLD, path, mesh, owned.local, attributes, output);

  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const Objects objects = objectsIn(file);
  EXPECT_EQ(objects.groups,
            (std::set<std::string>{format::kMesh, format::kPatches, format::kDisplay,
                                   format::kSolve, format::kFormFactors, format::kGroups}));
  const std::set<std::string> datasets = {format::kVertices,
                                          format::kTriangles,
                                          format::kArea,
                                          format::kNormal,
                                          format::kReflectance,
                                          format::kEmission,
                                          format::kRadiosity,
                                          format::kIrradiance,
                                          format::kRadiosityStderr,
                                          format::kRadiosityDiscretisation,
                                          format::kHidden,
                                          format::kSourceFace,
                                          format::kRank,
                                          format::kGroup,
                                          format::kDisplayVertices,
                                          format::kDisplayTriangles,
                                          format::kDisplayRadiosity,
                                          format::kDisplayTonemapped,
                                          format::kHistory,
                                          format::kRowSumHistogram,
                                          format::kRowSumBinEdges,
                                          format::kRowStart,
                                          format::kColumn,
                                          format::kValue,
                                          format::kGroupArea,
                                          format::kViewFactorError,
                                          format::kViewFactors};
  EXPECT_EQ(objects.datasets, datasets);
  for (const std::string& name : datasets) {
    std::set<std::string> expected = {attribute::kUnits, attribute::kDescription};
    if (name == format::kHistory) expected.insert(attribute::kColumns);
    if (name == format::kViewFactors) expected.insert(attribute::kGroupNames);
    if (name == format::kDisplayTonemapped) expected.insert(attribute::kMidpoint);
    EXPECT_EQ(attributesOf(file, name), expected) << name;
  }
  std::set<std::string> root = {
      attribute::kFormatVersion, attribute::kRanks,    attribute::kRaysPerPatch,
      attribute::kSeed,          attribute::kSolver,   attribute::kLeftOut,
      attribute::kIterations,    attribute::kResidual, attribute::kConverged,
      attribute::kScene,         attribute::kOptions,  attribute::kSolverChoice,
      attribute::kLengthUnit};
  for (const auto& [stage, seconds] : attributes.stageSeconds)
    root.insert(attribute::kStageTimePrefix + stage);
  for (const auto& [figure, value] : attributes.solveFigures)
    root.insert(attribute::kSolveFigurePrefix + figure);
  for (const auto& [name, version] : attributes.software)
    root.insert(attribute::kSoftwarePrefix + name);
  EXPECT_EQ(attributesOf(file), root);
  H5Fclose(file);
  EXPECT_EQ(readResult(path).attributes.formatVersion, format::kFormatVersion);
}

/// Ranks' blocks {first, count, total} as MPI_Allgather gathers them.
std::vector<int64_t> gathered(const std::vector<std::array<int64_t, 2>>& blocks, int64_t total) {
  std::vector<int64_t> values;
  for (const auto& [first, count] : blocks) values.insert(values.end(), {first, count, total});
  return values;
}

std::string failureOf(const std::vector<int64_t>& values, int64_t total) {
  try {
    checkRankBlocksTile(values, 3, total, {"holds rows", "hold", "rows"},
                        [](int, const int64_t*) {});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RankBlocks, TileInRankOrderIncludingEmptyBlocks) {
  EXPECT_EQ(failureOf(gathered({{0, 3}, {3, 0}, {3, 4}}, 7), 7), "");
  EXPECT_EQ(failureOf(gathered({{0, 0}}, 0), 0), "");
}

TEST(RankBlocks, AGapAnOverlapOrAShortfallIsRefusedInTheWriterSWords) {
  EXPECT_EQ(failureOf(gathered({{0, 3}, {4, 3}}, 7), 7),
            "rank 1 holds rows from 4 but the blocks of the ranks before it end at 3");
  EXPECT_EQ(failureOf(gathered({{0, 3}, {2, 5}}, 7), 7),
            "rank 1 holds rows from 2 but the blocks of the ranks before it end at 3");
  EXPECT_EQ(failureOf(gathered({{0, 3}, {3, 3}}, 7), 7), "the ranks hold 6 rows of 7");
  try {
    checkRankBlocksTile(gathered({{1, 2}}, 3), 3, 3, {"owns patches", "own", "patches"},
                        [](int, const int64_t*) {});
    FAIL() << "a block not starting at 0 passed";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "rank 0 owns patches from 1 but the blocks of the ranks before it end at 0");
  }
}

TEST(RankBlocks, EachRankIsCheckedBeforeItsBlock) {
  std::vector<int> seen;
  const auto values = gathered({{0, 3}, {5, 2}, {5, 2}}, 7);
  try {
    checkRankBlocksTile(values, 3, 7, {"holds rows", "hold", "rows"},
                        [&](int r, const int64_t* own) {
                          EXPECT_EQ(own, &values[3 * static_cast<size_t>(r)]);
                          seen.push_back(r);
                        });
    FAIL() << "a gap passed";
  } catch (const std::invalid_argument&) {
  }
  EXPECT_EQ(seen, (std::vector<int>{0, 1}));  // rank 1's own check came before its gap
}

}  // namespace
}  // namespace radiosity
