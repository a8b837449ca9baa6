// The checkpoint file as writeCheckpoint writes it collectively: read back exactly under any
// decomposition, whole or not at all, and described by `radiosity info`. Runs on one rank and
// on N with `mpirun -n N build/tests/io_checkpoint_roundtrip_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <chrono>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "checkpoint_fixture.h"
#include "core/error.h"
#include "core/mesh.h"
#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::blockStart;
using testing::CheckpointTest;
using testing::expectSame;
using testing::mixedSamplesOf;
using testing::myPart;
using testing::namesIn;
using testing::partOf;
using testing::readBytes;
using testing::worldRank;
using testing::worldSize;
using testing::writeText;

TEST_F(CheckpointTest, RoundTripOnTheSameDecompositionIsExactAndLeavesOnlyTheFile) {
  const int64_t np = 23;
  const fs::path path = dir_ / "ck.h5";
  const Checkpoint mine = myPart(np);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  const Checkpoint back = readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                                         mine.rows.tally.firstRow + mine.rows.tally.rowCount());
  expectSame(back, mine);
  EXPECT_EQ(namesIn(dir_), std::set<std::string>{"ck.h5"});
  EXPECT_TRUE(isCheckpoint(path.string()));
}

// The refinement rounds (rank 0's) come back whole, from readCheckpoint and alone; none is none.
TEST_F(CheckpointTest, RefinementRoundsRoundTrip) {
  const fs::path path = dir_ / "ck.h5";
  Checkpoint mine = myPart(17);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  EXPECT_EQ(readCheckpointRefinement(MPI_COMM_WORLD, path.string()).rounds(), 0);
  mine.refinement.add({3, 1, 4}, 25);
  mine.refinement.add({}, 25);
  mine.refinement.add({int64_t{1} << 40, 0}, 31);
  mine.refinement.addMerges({7, int64_t{1} << 41});  // the last round's bisections undone
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  for (const RefinementHistory& back :
       {readCheckpointRefinement(MPI_COMM_WORLD, path.string()),
        readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                       mine.rows.tally.firstRow + mine.rows.tally.rowCount())
            .refinement}) {
    EXPECT_EQ(back.roundStart, mine.refinement.roundStart);
    EXPECT_EQ(back.marked, mine.refinement.marked);
    EXPECT_EQ(back.patchesAfter, mine.refinement.patchesAfter);
    EXPECT_EQ(back.mergedStart, (std::vector<int64_t>{0, 0, 0, 2}));
    EXPECT_EQ(back.merged, mine.refinement.merged);
  }
  EXPECT_NE(describeCheckpoint(path.string())
                .find("refinement rounds: 3 (5 patches split, 2 bisections undone)"),
            std::string::npos)
      << describeCheckpoint(path.string());
}

// The mesh (rank 0's, every rank holds it alike) comes back whole with its input fingerprint, in
// the scene's coordinates to the bit; a checkpoint without one gives none.
TEST_F(CheckpointTest, MeshRoundTrips) {
  const fs::path path = dir_ / "ck.h5";
  Checkpoint mine = myPart(2);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  EXPECT_TRUE(readCheckpointMesh(MPI_COMM_WORLD, path.string()).empty());
  const CheckpointMesh mesh{"2 triangles, hash 0123, max-area 0.5, contacts cut",
                            {{0, 0, 0}, {1e30, 0, 0}, {0, 1.0 / 3, -1e-30}, {0.1, 0.2, 0.3}},
                            {{0, 1, 2}, {1, 3, 2}},
                            {7, 0}};
  mine.mesh = viewOf(mesh);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  const CheckpointMesh back = readCheckpointMesh(MPI_COMM_WORLD, path.string());
  EXPECT_EQ(back.input, mesh.input);
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  for (size_t v = 0; v < back.vertices.size(); ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.vertices[v][k], mesh.vertices[v][k]);
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(back.sourceFace, mesh.sourceFace);
}

TEST_F(CheckpointTest, EveryDatasetIsChunkedWithFletcher32) {
  const fs::path path = dir_ / "ck.h5";
  Checkpoint mine = myPart(10);
  const CheckpointMesh mesh{"input", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, {0}};
  mine.mesh = viewOf(mesh);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  if (worldRank() != 0) return;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name :
       {"/formfactors/samples", "/formfactors/row_start", "/formfactors/column", "/formfactors/sum",
        "/solve/radiosity", "/solve/history", "/refinement/marked", "/refinement/round_start",
        "/refinement/patches", "/mesh/vertices", "/mesh/triangles", "/mesh/source_face"}) {
    const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
    ASSERT_GE(dataset, 0) << name;
    const hid_t creation = H5Dget_create_plist(dataset);
    EXPECT_EQ(H5Pget_layout(creation), H5D_CHUNKED) << name;
    unsigned flags = 0;
    size_t count = 0;
    char filterName[64];
    EXPECT_GE(H5Pget_filter_by_id2(creation, H5Z_FILTER_FLETCHER32, &flags, &count, nullptr,
                                   sizeof filterName, filterName, nullptr),
              0)
        << name;
    H5Pclose(creation);
    H5Dclose(dataset);
  }
  H5Fclose(file);
}

TEST_F(CheckpointTest, ReadsUnderAnotherDecomposition) {
  const int64_t np = 31;
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(np));
  // Every rank the whole range.
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 0, np), partOf(np, 0, np));
  // Halves, crossing the writers' blocks.
  const int64_t first = worldRank() % 2 == 0 ? 0 : np / 2, end = worldRank() % 2 == 0 ? np / 2 : np;
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), first, end), partOf(np, first, end));
  // Uneven blocks in reverse order, the first rank reading nothing.
  const int size = worldSize(), rank = worldRank();
  const int64_t from = rank == 0 ? np : np - blockStart(np, size - rank, size);
  const int64_t to = rank == 0 ? np : np - blockStart(np, size - rank - 1, size);
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), std::min(from, to), to),
             partOf(np, std::min(from, to), to));
  // Single rows at both ends and an empty range.
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), np - 1, np), partOf(np, np - 1, np));
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 0, 1), partOf(np, 0, 1));
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 5, 5), partOf(np, 5, 5));
}

TEST_F(CheckpointTest, MixedSamplesPerRowRoundTripUnderAnotherSplit) {
  // 0, 256 and 1024 samples side by side (a restart with more rays extends rows one piece at a
  // time), and whatever rows.samples the writer has is ignored.
  const int64_t np = 37;
  const fs::path path = dir_ / "ck.h5";
  Checkpoint mine = myPart(np, mixedSamplesOf);
  mine.rows.tally.samples = 99 + worldRank();
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  // Every rank the whole range: all three counts, the largest 1024.
  const Checkpoint all = readCheckpoint(MPI_COMM_WORLD, path.string(), 0, np);
  expectSame(all, partOf(np, 0, np, mixedSamplesOf));
  EXPECT_EQ(all.rows.tally.samples, 1024);
  EXPECT_EQ(all.rows.rowsFinished(), np - (np + 4) / 5);
  EXPECT_EQ(std::set<int64_t>(all.rows.rowSamples.begin(), all.rows.rowSamples.end()),
            (std::set<int64_t>{0, 256, 1024}));
  // Uneven blocks in reverse order, crossing the writers' blocks; the first rank reads nothing.
  const int size = worldSize(), rank = worldRank();
  const int64_t to = rank == 0 ? np : np - blockStart(np, size - rank - 1, size);
  const int64_t from = rank == 0 ? np : np - blockStart(np, size - rank, size);
  const Checkpoint part = readCheckpoint(MPI_COMM_WORLD, path.string(), from, to);
  expectSame(part, partOf(np, from, to, mixedSamplesOf));
  // Rows 6 and 7 only (256 samples each): the largest is 256; row 5 only: none sampled, 0.
  EXPECT_EQ(readCheckpoint(MPI_COMM_WORLD, path.string(), 6, 8).rows.tally.samples, 256);
  EXPECT_EQ(readCheckpoint(MPI_COMM_WORLD, path.string(), 5, 6).rows.tally.samples, 0);
  // Blocks in rank order but 3 rows off the writers' (rank 0 takes 3 more): read, written back
  // under that split, and read whole again, the rows are as made.
  auto shifted = [&](int r) { return r == 0 ? 0 : std::min(np, blockStart(np, r, size) + 3); };
  const int64_t first = shifted(rank), end = rank == size - 1 ? np : shifted(rank + 1);
  const Checkpoint moved = readCheckpoint(MPI_COMM_WORLD, path.string(), first, end);
  expectSame(moved, partOf(np, first, end, mixedSamplesOf));
  const fs::path again = dir_ / "again.h5";
  writeCheckpoint(MPI_COMM_WORLD, again.string(), moved);
  expectSame(readCheckpoint(MPI_COMM_WORLD, again.string(), 0, np), all);
  expectSame(readCheckpoint(MPI_COMM_WORLD, again.string(), from, to), part);
}

TEST_F(CheckpointTest, WrittenByFewerRanksReadByAll) {
  // Ranks [0, size - 1) write (all of them on one rank), every rank reads its block.
  const int64_t np = 40;
  const fs::path path = dir_ / "ck.h5";
  const int rank = worldRank(), size = worldSize();
  const int writers = size > 1 ? size - 1 : 1;
  MPI_Comm comm = MPI_COMM_NULL;
  MPI_Comm_split(MPI_COMM_WORLD, rank < writers ? 0 : MPI_UNDEFINED, rank, &comm);
  if (comm != MPI_COMM_NULL) {
    writeCheckpoint(comm, path.string(),
                    partOf(np, blockStart(np, rank, writers), blockStart(np, rank + 1, writers)));
    MPI_Comm_free(&comm);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const int64_t first = blockStart(np, rank, size), end = blockStart(np, rank + 1, size);
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), first, end), partOf(np, first, end));
}

TEST_F(CheckpointTest, SeveralChunksSharedBetweenRanks) {
  // More than 2^20 rows: every dataset has several chunks, and the ranks' blocks end inside
  // them, so parallel HDF5 has to merge the ranks' parts of a filtered chunk.
  const int64_t np = (int64_t{1} << 20) + 54321;
  const fs::path path = dir_ / "big.h5";
  const Checkpoint mine = myPart(np);
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                            mine.rows.tally.firstRow + mine.rows.tally.rowCount()),
             mine);
  // A block around the chunk boundary of the 1-D datasets.
  const int64_t first = (int64_t{1} << 20) - 1000 - worldRank(), end = first + 2001;
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), first, end), partOf(np, first, end));
}

TEST_F(CheckpointTest, NothingSampledAndNoHistory) {
  const int64_t np = 9;
  Checkpoint mine = myPart(np);
  mine.stage = "formfactors";
  mine.progress.channelState = {0, 0, 0};
  mine.progress.history = SolveHistory{};
  std::fill(mine.rows.rowSamples.begin(), mine.rows.rowSamples.end(), 0);
  mine.rows.tally.rowStart.assign(mine.rows.tally.rowCount() + 1, 0);
  mine.rows.tally.column.clear();
  mine.rows.tally.sum.clear();
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  const Checkpoint back = readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                                         mine.rows.tally.firstRow + mine.rows.tally.rowCount());
  expectSame(back, mine);
  EXPECT_EQ(back.rows.rowsFinished(), 0);
  EXPECT_EQ(back.progress.history.size(), 0u);
  // No radiosity yet: written as zeros; no balance: as ones.
  mine.progress.radiosity.clear();
  mine.rowBalance.clear();
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  const Checkpoint zeros = readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                                          mine.rows.tally.firstRow + mine.rows.tally.rowCount());
  EXPECT_EQ(zeros.progress.radiosity, std::vector<Rgb>(mine.rows.tally.rowCount(), Rgb{0, 0, 0}));
  EXPECT_EQ(zeros.rowBalance, std::vector<double>(mine.rows.tally.rowCount(), 1.0));
}

TEST_F(CheckpointTest, NoPatchesAtAll) {
  const fs::path path = dir_ / "ck.h5";
  Checkpoint empty = partOf(0, 0, 0);
  empty.identity.clear();
  writeCheckpoint(MPI_COMM_WORLD, path.string(), empty);
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 0, 0), empty);
  const std::string text = describeCheckpoint(path.string());
  EXPECT_NE(text.find("patches: 0"), std::string::npos) << text;
}

// The outputs of one command appear together: a checkpoint staged with another output is not
// in place before commit(), and when the other output fails the checkpoint is not renamed.
TEST_F(CheckpointTest, StagedOutputsAppearOnlyTogetherAtCommit) {
  const int64_t np = 12;
  const fs::path checkpoint = dir_ / "ck.h5", other = dir_ / "other.txt";
  {
    CollectiveOutputs outputs(MPI_COMM_WORLD);
    stageCheckpoint(outputs, checkpoint.string(), myPart(np));
    const std::string temporary = outputs.stage(other.string());
    if (worldRank() == 0) writeText(temporary, "other");
    MPI_Barrier(MPI_COMM_WORLD);
    EXPECT_FALSE(fs::exists(checkpoint));
    EXPECT_FALSE(fs::exists(other));
    outputs.commit();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (worldRank() == 0) {
    EXPECT_EQ(readBytes(other), "other");
  }
  EXPECT_TRUE(isCheckpoint(checkpoint.string()));
  const std::string before = worldRank() == 0 ? readBytes(checkpoint) : std::string();

  // The second output fails after the checkpoint was written: neither is replaced, no
  // temporary is left.
  Checkpoint unknown = myPart(np);
  unknown.stage = "later";
  try {
    CollectiveOutputs outputs(MPI_COMM_WORLD);
    stageCheckpoint(outputs, checkpoint.string(), myPart(np, [](int64_t) { return int64_t{2}; }));
    stageCheckpoint(outputs, (dir_ / "second.h5").string(), unknown);
    outputs.commit();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (worldRank() == 0) {
    EXPECT_EQ(readBytes(checkpoint), before);
    EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"ck.h5", "other.txt"}));
  }
}

TEST_F(CheckpointTest, FailedWritesLeaveTheExistingCheckpoint) {
  const int64_t np = 12;
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(np));
  const std::string before = worldRank() == 0 ? readBytes(path) : std::string();
  // Bad rows on the last rank only: every rank fails, before anything is written.
  Checkpoint bad = myPart(np);
  if (worldRank() == worldSize() - 1) {
    bad.stage = "done";
    bad.rows.tally.column.push_back(np);
    bad.rows.tally.sum.push_back(1);
    bad.rows.tally.rowStart.back() += 1;
    bad.rows.rowSamples.back() = 1024;
  }
  try {
    writeCheckpoint(MPI_COMM_WORLD, path.string(), bad);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    ADD_FAILURE() << "not an input error: " << e.what();
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("column 12 of 12"), std::string::npos) << e.what();
  }
  // An unknown stage (rank 0's is the one written, so every rank finds it).
  Checkpoint unknown = myPart(np);
  unknown.stage = "later";
  EXPECT_THROW(writeCheckpoint(MPI_COMM_WORLD, path.string(), unknown), Error);
  MPI_Barrier(MPI_COMM_WORLD);
  if (worldRank() == 0) {
    EXPECT_EQ(readBytes(path), before);
    EXPECT_EQ(namesIn(dir_), std::set<std::string>{"ck.h5"});
  }
  // A directory under the name: the file is written but cannot replace it.
  const fs::path directory = dir_ / "taken";
  if (worldRank() == 0) {
    fs::create_directory(directory);
    writeText(directory / "keep", "x");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    writeCheckpoint(MPI_COMM_WORLD, directory.string(), myPart(np));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kFailure);
    EXPECT_NE(std::string(e.what()).find("rename"), std::string::npos) << e.what();
  }
  // A directory that does not exist.
  EXPECT_THROW(writeCheckpoint(MPI_COMM_WORLD, (dir_ / "none" / "ck.h5").string(), myPart(np)),
               Error);
  MPI_Barrier(MPI_COMM_WORLD);
  if (worldRank() == 0) {
    EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"ck.h5", "taken"}));
    EXPECT_EQ(namesIn(directory), std::set<std::string>{"keep"});
    EXPECT_EQ(readBytes(path), before);
  }
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 0, np), partOf(np, 0, np));
}

TEST_F(CheckpointTest, StallHookWaitsBeforeTheRename) {
  const fs::path path = dir_ / "ck.h5";
  setenv("RADIOSITY_TEST_CHECKPOINT_STALL", "0.3", 1);
  const auto start = std::chrono::steady_clock::now();
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(8));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  unsetenv("RADIOSITY_TEST_CHECKPOINT_STALL");
  EXPECT_GE(seconds, 0.3);
  expectSame(readCheckpoint(MPI_COMM_WORLD, path.string(), 0, 8), partOf(8, 0, 8));
}

TEST_F(CheckpointTest, DescriptionNamesStageCountsIdentityAndChannels) {
  const int64_t np = 20;  // sampled (1024 each): every row but 1, 5, 9, 13, 17
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(np));
  const std::string text = describeCheckpoint(path.string());
  for (const char* expected :
       {"checkpoint", "stage: solve", "patches: 20", "rows sampled: 15 of 20 (75.0%)",
        "samples per row: 1024 (15 rows)\n", "scene = builtin:cornell?rho=0.5 (größer)",
        "max_area = 0.01", "      seed = 7", "red: done", "green: in progress", "blue: not started",
        "solve history: 5 entries"})
    EXPECT_NE(text.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << text;
}

TEST_F(CheckpointTest, DescriptionCountsTheRowsOfEachNumberOfSamples) {
  const int64_t np = 20;
  const fs::path mixed = dir_ / "mixed.h5", full = dir_ / "full.h5", none = dir_ / "none.h5";
  // 0 samples: rows 0, 5, 10, 15; 256: rows 1, 2, 6, 7, ...; 1024: rows 3, 4, 8, 9, ...
  writeCheckpoint(MPI_COMM_WORLD, mixed.string(), myPart(np, mixedSamplesOf));
  writeCheckpoint(MPI_COMM_WORLD, full.string(), myPart(np, [](int64_t) { return int64_t{1024}; }));
  Checkpoint nothing = myPart(np, [](int64_t) { return int64_t{0}; });
  nothing.stage = "formfactors";
  writeCheckpoint(MPI_COMM_WORLD, none.string(), nothing);
  auto expectLines = [](const fs::path& path, const std::vector<std::string>& lines) {
    const std::string text = describeCheckpoint(path.string());
    for (const std::string& line : lines)
      EXPECT_NE(text.find("  " + line + "\n"), std::string::npos) << "'" << line << "' not in:\n"
                                                                  << text;
  };
  expectLines(mixed,
              {"rows sampled: 16 of 20 (80.0%)", "samples per row: 256 (8 rows), 1024 (8 rows)"});
  expectLines(full, {"rows sampled: 20 of 20 (100.0%)", "samples per row: 1024 (all)"});
  expectLines(none, {"rows sampled: 0 of 20 (0.0%)", "samples per row: none yet"});
}

}  // namespace
}  // namespace radiosity
