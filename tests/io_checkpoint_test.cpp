// The checkpoint file: what writeCheckpoint writes collectively, readCheckpoint reads back exactly
// under any decomposition, the file appears whole or not at all, and damage to it (flipped bytes,
// truncation, inconsistent contents) is an InputError on every rank. Runs on one rank as a plain
// executable and on N ranks with `mpirun -n N build/tests/io_checkpoint_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;

using testing::worldRank;
using testing::worldSize;

/// The first row of `rank` of `size` when np rows are dealt in contiguous blocks.
int64_t blockStart(int64_t np, int rank, int size) { return np * rank / size; }

/// The samples of row i of a made-up checkpoint: rows i % 4 == 1 are not sampled yet, the
/// others have 1024 samples.
int64_t samplesOf(int64_t i) { return i % 4 != 1 ? 1024 : 0; }

/// Mixed samples, as a restart with more rays leaves them: rows i % 5 == 0 not sampled, rows
/// i % 5 == 1 or 2 with 256 samples, the others with 1024.
int64_t mixedSamplesOf(int64_t i) {
  const int64_t k = i % 5;
  return k == 0 ? 0 : k <= 2 ? 256 : 1024;
}

SolveHistory someHistory() {
  SolveHistory h;
  h.channel = {0, 0, 0, 1, 1};
  h.iteration = {0, 1, 2, 0, int64_t{1} << 53};
  h.residual = {1.0, 1.0 / 3, 5e-324, 0.1, 1e308};
  h.seconds = {0.0, 1e-6, 0.1 + 0.2, 0.5, 12345.678901234567};
  return h;
}

/// Rows [first, end) of the made-up checkpoint of np patches, with everything else. Row i has
/// samples(i) samples; a row without any is empty, one with some has i % 3 entries (so some
/// sampled rows are empty too), with sums that need all 64 bits.
Checkpoint partOf(int64_t np, int64_t first, int64_t end, int64_t (*samples)(int64_t) = samplesOf) {
  Checkpoint c;
  c.stage = "solve";
  c.identity = {{"scene", "builtin:cornell?rho=0.5 (größer)"},
                {"max_area", "0.01"},
                {"options", "rays = 1000\nseed = 7\n"}};
  c.patchCount = np;
  c.rows.tally.firstRow = first;
  c.progress.channelState = {2, 1, 0};
  c.progress.history = someHistory();
  for (int64_t i = first; i < end; ++i) {
    c.rows.rowSamples.push_back(samples(i));
    const int64_t entries = samples(i) > 0 ? i % 3 : 0;
    for (int64_t k = 0; k < entries; ++k) {
      c.rows.tally.column.push_back((i + 1 + 2 * k) % np);
      c.rows.tally.sum.push_back(((i + 1) << 30) * (k + 1) - 7 + (k == 1 ? INT64_C(1) << 62 : 0));
    }
    c.rows.tally.rowStart.push_back(static_cast<int64_t>(c.rows.tally.column.size()));
    c.progress.radiosity.push_back({i + 0.25, 1.0 / (i + 3), -1e-300 * static_cast<double>(i)});
  }
  return c;
}

/// This rank's block of the made-up checkpoint.
Checkpoint myPart(int64_t np, int64_t (*samples)(int64_t) = samplesOf) {
  return partOf(np, blockStart(np, worldRank(), worldSize()),
                blockStart(np, worldRank() + 1, worldSize()), samples);
}

/// `a` (read back) holds what `b` (written, or made up alike) does. rows.samples is not part of
/// a checkpoint: the reader sets it to the largest of its rowSamples, 0 if it has no rows.
void expectSame(const Checkpoint& a, const Checkpoint& b) {
  EXPECT_EQ(a.stage, b.stage);
  EXPECT_EQ(a.identity, b.identity);
  EXPECT_EQ(a.patchCount, b.patchCount);
  EXPECT_EQ(a.rows.tally.firstRow, b.rows.tally.firstRow);
  EXPECT_EQ(a.rows.tally.rowStart, b.rows.tally.rowStart);
  EXPECT_EQ(a.rows.tally.column, b.rows.tally.column);
  EXPECT_EQ(a.rows.tally.sum, b.rows.tally.sum);
  EXPECT_EQ(a.rows.rowSamples, b.rows.rowSamples);
  EXPECT_EQ(a.rows.tally.samples,
            a.rows.rowSamples.empty()
                ? 0
                : *std::max_element(a.rows.rowSamples.begin(), a.rows.rowSamples.end()));
  EXPECT_EQ(a.progress.channelState, b.progress.channelState);
  EXPECT_EQ(a.progress.radiosity, b.progress.radiosity);
  EXPECT_EQ(a.progress.history.channel, b.progress.history.channel);
  EXPECT_EQ(a.progress.history.iteration, b.progress.history.iteration);
  EXPECT_EQ(a.progress.history.residual, b.progress.history.residual);
  EXPECT_EQ(a.progress.history.seconds, b.progress.history.seconds);
  EXPECT_EQ(a.rows.rowsFinished(), b.rows.rowsFinished());
}

std::set<std::string> namesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

/// Each test gets a fresh directory, the same on every rank.
class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_FALSE(dir_.empty()); }

  radiosity::testing::SharedTempDir temp_{"io_checkpoint_test"};
  fs::path dir_ = temp_.path();
};

/// Expects `call` to throw InputError (exit code 3) on this rank, mentioning every word.
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
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
}

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

TEST_F(CheckpointTest, EveryDatasetIsChunkedWithFletcher32) {
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(10));
  if (worldRank() != 0) return;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name : {"/formfactors/samples", "/formfactors/row_start", "/formfactors/column",
                           "/formfactors/sum", "/solve/radiosity", "/solve/history"}) {
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
  // No radiosity yet: written as zeros.
  mine.progress.radiosity.clear();
  writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
  const Checkpoint zeros = readCheckpoint(MPI_COMM_WORLD, path.string(), mine.rows.tally.firstRow,
                                          mine.rows.tally.firstRow + mine.rows.tally.rowCount());
  EXPECT_EQ(zeros.progress.radiosity, std::vector<Rgb>(mine.rows.tally.rowCount(), Rgb{0, 0, 0}));
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
  if (worldRank() == 0) EXPECT_EQ(readBytes(other), "other");
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

/// Flips bytes in the middle of the first stored chunk of `dataset` in `path` (serial).
void flipChunkBytes(const fs::path& path, const char* dataset) {
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t data = H5Dopen2(file, dataset, H5P_DEFAULT);
  ASSERT_GE(data, 0);
  const hid_t space = H5Dget_space(data);
  hsize_t offset[2] = {}, chunks = 0;
  unsigned mask = 0;
  haddr_t address = HADDR_UNDEF;
  hsize_t size = 0;
  ASSERT_GE(H5Dget_num_chunks(data, space, &chunks), 0);
  ASSERT_GE(chunks, 1u);
  ASSERT_GE(H5Dget_chunk_info(data, space, 0, offset, &mask, &address, &size), 0);
  H5Sclose(space);
  H5Dclose(data);
  H5Fclose(file);
  ASSERT_NE(address, HADDR_UNDEF);
  ASSERT_GE(size, 8u);
  std::fstream stream(path, std::ios::in | std::ios::out | std::ios::binary);
  const std::streamoff where = static_cast<std::streamoff>(address + size / 2 - 2);
  stream.seekg(where);
  char bytes[3];
  stream.read(bytes, 3);
  for (char& b : bytes) b = static_cast<char>(b ^ 0x5A);
  stream.seekp(where);
  stream.write(bytes, 3);
}

TEST_F(CheckpointTest, FlippedBytesAreFoundOnEveryRank) {
  const int64_t np = 20;
  const fs::path good = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, good.string(), myPart(np));
  const std::vector<const char*> datasets = {"/formfactors/sum",       "/formfactors/column",
                                             "/formfactors/row_start", "/formfactors/samples",
                                             "/solve/radiosity",       "/solve/history"};
  if (worldRank() == 0) {
    for (size_t d = 0; d < datasets.size(); ++d) {
      const fs::path copy = dir_ / ("bad" + std::to_string(d) + ".h5");
      fs::copy_file(good, copy);
      flipChunkBytes(copy, datasets[d]);
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  for (size_t d = 0; d < datasets.size(); ++d) {
    const std::string bad = (dir_ / ("bad" + std::to_string(d) + ".h5")).string();
    SCOPED_TRACE(datasets[d]);
    // Rank 0 reads no rows (so only the others meet the damaged chunk, except in the history,
    // which every rank reads): every rank must throw all the same.
    const int64_t end = worldRank() == 0 && worldSize() > 1 ? 0 : np;
    expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, bad, 0, end); },
                     {bad, "corrupt", "checksum", datasets[d]});
    // Still recognised as a checkpoint (the damage is in the data, not the metadata).
    EXPECT_TRUE(isCheckpoint(bad));
  }
}

TEST_F(CheckpointTest, FlippedMetadataBytesAreFound) {
  // The file format's object headers carry checksums too: damage one in the middle.
  const fs::path good = dir_ / "ck.h5", bad = dir_ / "bad.h5";
  writeCheckpoint(MPI_COMM_WORLD, good.string(), myPart(12));
  if (worldRank() == 0) {
    fs::copy_file(good, bad);
    const hid_t file = H5Fopen(bad.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t dataset = H5Dopen2(file, "/formfactors/column", H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    H5O_info_t info;
    ASSERT_GE(H5Oget_info2(dataset, &info, H5O_INFO_BASIC | H5O_INFO_HDR), 0);
    H5Dclose(dataset);
    H5Fclose(file);
    ASSERT_GE(info.hdr.version, 2u);  // version 2 headers have checksums
    std::fstream stream(bad, std::ios::in | std::ios::out | std::ios::binary);
    const std::streamoff where = static_cast<std::streamoff>(info.addr + info.hdr.space.total / 2);
    stream.seekg(where);
    const char byte = static_cast<char>(stream.get() ^ 0x24);
    stream.seekp(where);
    stream.put(byte);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, bad.string(), 0, 12); },
                   {bad.string(), "corrupt", "checksum", "/formfactors/column"});
}

TEST_F(CheckpointTest, TruncatedFileIsAnInputError) {
  const fs::path good = dir_ / "ck.h5", cut = dir_ / "cut.h5";
  writeCheckpoint(MPI_COMM_WORLD, good.string(), myPart(16));
  if (worldRank() == 0) {
    fs::copy_file(good, cut);
    fs::resize_file(cut, fs::file_size(good) / 2);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, cut.string(), 0, 16); },
                   {cut.string(), "corrupt"});
  expectInputError([&] { describeCheckpoint(cut.string()); }, {cut.string()});
  EXPECT_FALSE(isCheckpoint(cut.string()));
}

/// Rewrites dataset `name` of a checkpoint (serial HDF5, so the checksum is right) with
/// `change` applied to its values.
template <class T, class Change>
void rewrite(const fs::path& path, const char* name, hid_t memoryType, Change change) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
  ASSERT_GE(dataset, 0);
  const hid_t space = H5Dget_space(dataset);
  std::vector<T> values(H5Sget_simple_extent_npoints(space));
  H5Sclose(space);
  ASSERT_GE(H5Dread(dataset, memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  change(values);
  ASSERT_GE(H5Dwrite(dataset, memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(dataset);
  H5Fclose(file);
}

void rewriteChannelState(const fs::path& path, int blue) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t attribute = H5Aopen(file, "channel_state", H5P_DEFAULT);
  ASSERT_GE(attribute, 0);
  const int states[3] = {2, 2, blue};
  ASSERT_GE(H5Awrite(attribute, H5T_NATIVE_INT, states), 0);
  H5Aclose(attribute);
  H5Fclose(file);
}

TEST_F(CheckpointTest, InconsistentContentsAreNamed) {
  const int64_t np = 14;
  const fs::path good = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, good.string(), myPart(np));
  auto copy = [&](const char* name) {
    const fs::path to = dir_ / name;
    fs::copy_file(good, to);
    return to;
  };
  if (worldRank() == 0) {
    rewrite<int64_t>(copy("column.h5"), "/formfactors/column", H5T_NATIVE_INT64,
                     [&](std::vector<int64_t>& v) { v[1] = np + 5; });
    rewrite<int64_t>(copy("down.h5"), "/formfactors/row_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[4] = v[5] + 1; });
    rewrite<int64_t>(copy("end.h5"), "/formfactors/row_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v.back() -= 1; });
    rewrite<int64_t>(copy("negative.h5"), "/formfactors/samples", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[3] = -7; });
    rewrite<int64_t>(copy("huge.h5"), "/formfactors/samples", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[np - 1] = int64_t{1} << 32; });
    // Row 1 is not sampled: taking row 2's samples leaves it with its 2 entries.
    rewrite<int64_t>(copy("unsampled.h5"), "/formfactors/samples", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[2] = 0; });
    rewriteChannelState(copy("state.h5"), 3);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  auto read = [&](const char* name) {
    return [&, name] { readCheckpoint(MPI_COMM_WORLD, (dir_ / name).string(), 0, np); };
  };
  expectInputError(read("column.h5"), {"column.h5", "corrupt", "/formfactors/column", "19"});
  expectInputError(read("down.h5"), {"down.h5", "corrupt", "/formfactors/row_start", "down"});
  expectInputError(read("end.h5"), {"end.h5", "corrupt", "/formfactors/row_start"});
  expectInputError(read("negative.h5"), {"negative.h5", "corrupt", "/formfactors/samples", "-7"});
  expectInputError(read("huge.h5"),
                   {"huge.h5", "corrupt", "/formfactors/samples", "4294967296", "row 13"});
  expectInputError(read("unsampled.h5"),
                   {"unsampled.h5", "corrupt", "row 2", "no samples", "2 entries"});
  expectInputError(read("state.h5"), {"state.h5", "channel_state", "blue", "3"});
}

TEST_F(CheckpointTest, OtherFilesAreNotCheckpoints) {
  const fs::path text = dir_ / "words.h5", result = dir_ / "result.h5";
  if (worldRank() == 0) writeText(text, "not HDF5 at all\n");
  // A result file: HDF5, but no checkpoint.
  Mesh mesh;
  LocalSolution local;
  writeResult(MPI_COMM_WORLD, result.string(), mesh, local, ResultAttributes{});
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_FALSE(isCheckpoint(result.string()));
  EXPECT_FALSE(isCheckpoint(text.string()));
  EXPECT_FALSE(isCheckpoint((dir_ / "absent.h5").string()));
  EXPECT_FALSE(isCheckpoint(dir_.string()));
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, result.string(), 0, 0); },
                   {result.string(), "not a checkpoint"});
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, text.string(), 0, 0); },
                   {text.string(), "not a checkpoint"});
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, (dir_ / "absent.h5").string(), 0, 0); },
                   {"absent.h5", "no such file"});
  expectInputError([&] { describeCheckpoint(result.string()); },
                   {result.string(), "not a checkpoint"});
}

TEST_F(CheckpointTest, RowsBeyondThePatchesAreAnInputError) {
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(10));
  expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, path.string(), 5, 11); },
                   {path.string(), "10 patches"});
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

TEST_F(CheckpointTest, BadSamplesPerRowAreRefusedBeforeWriting) {
  const int64_t np = 12;
  const fs::path path = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, path.string(), myPart(np));
  const std::string before = worldRank() == 0 ? readBytes(path) : std::string();
  // Each made bad on the last rank only: every rank fails with its message.
  struct Case {
    const char* mentions;
    void (*spoil)(Checkpoint&);
  };
  const Case cases[] = {
      {"samples, not 0 to 2^32 - 1", [](Checkpoint& c) { c.rows.rowSamples.back() = -1; }},
      {"4294967296 samples, not 0 to 2^32 - 1",
       [](Checkpoint& c) { c.rows.rowSamples.back() = int64_t{1} << 32; }},
      {"counts for", [](Checkpoint& c) { c.rows.rowSamples.push_back(1024); }},
      {"counts for", [](Checkpoint& c) { c.rows.rowSamples.clear(); }},
      // Row np - 1 = 11 has 2 entries (11 % 3).
      {"row 11 has no samples but 2 entries", [](Checkpoint& c) { c.rows.rowSamples.back() = 0; }},
  };
  for (const Case& bad : cases) {
    SCOPED_TRACE(bad.mentions);
    Checkpoint mine = myPart(np);
    if (worldRank() == worldSize() - 1) bad.spoil(mine);
    try {
      writeCheckpoint(MPI_COMM_WORLD, path.string(), mine);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      ADD_FAILURE() << "not an input error: " << e.what();
    } catch (const Error& e) {
      EXPECT_EQ(e.exitCode(), exit_code::kFailure);
      EXPECT_NE(std::string(e.what()).find(bad.mentions), std::string::npos) << e.what();
    }
  }
  // The largest allowed count is fine.
  Checkpoint most = myPart(np);
  for (int64_t& samples : most.rows.rowSamples) samples = samples > 0 ? (int64_t{1} << 32) - 1 : 0;
  const fs::path large = dir_ / "large.h5";
  writeCheckpoint(MPI_COMM_WORLD, large.string(), most);
  expectSame(readCheckpoint(MPI_COMM_WORLD, large.string(), most.rows.tally.firstRow,
                            most.rows.tally.firstRow + most.rows.tally.rowCount()),
             most);
  MPI_Barrier(MPI_COMM_WORLD);
  if (worldRank() == 0) {
    EXPECT_EQ(readBytes(path), before);
    EXPECT_EQ(namesIn(dir_), (std::set<std::string>{"ck.h5", "large.h5"}));
  }
}

TEST_F(CheckpointTest, OtherFormatVersionsAreRefused) {
  const int64_t np = 8;
  const fs::path good = dir_ / "ck.h5";
  writeCheckpoint(MPI_COMM_WORLD, good.string(), myPart(np));
  auto setVersion = [&](const char* name, int version) {
    const fs::path to = dir_ / name;
    fs::copy_file(good, to);
    const hid_t file = H5Fopen(to.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t attribute = H5Aopen(file, "format_version", H5P_DEFAULT);
    ASSERT_GE(attribute, 0);
    int stored = 0;
    ASSERT_GE(H5Aread(attribute, H5T_NATIVE_INT, &stored), 0);
    EXPECT_EQ(stored, 2);
    ASSERT_GE(H5Awrite(attribute, H5T_NATIVE_INT, &version), 0);
    H5Aclose(attribute);
    H5Fclose(file);
  };
  if (worldRank() == 0) {
    setVersion("v1.h5", 1);
    setVersion("v3.h5", 3);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  for (const char* name : {"v1.h5", "v3.h5"}) {
    const std::string path = (dir_ / name).string();
    const std::string version = name[1] == '1' ? "version 1" : "version 3";
    expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, path, 0, np); },
                     {path, "unsupported checkpoint format version", version});
    expectInputError([&] { describeCheckpoint(path); },
                     {path, "unsupported checkpoint format version", version});
    EXPECT_TRUE(isCheckpoint(path));  // a checkpoint, of a format this program does not read
  }
}

}  // namespace
}  // namespace radiosity
