// Checkpoints refused: damage (flipped bytes, truncation, inconsistent contents), other files
// and other format versions are an InputError on every rank, and bad rows are refused before
// writing. Runs on one rank and on N with `mpirun -n N build/tests/io_checkpoint_refusal_test`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "checkpoint_fixture.h"
#include "core/error.h"
#include "expect_error.h"
#include "hdf5_rewrite.h"
#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::CheckpointTest;
using testing::expectSame;
using testing::myPart;
using testing::namesIn;
using testing::readBytes;
using testing::rewrite;
using testing::worldRank;
using testing::worldSize;
using testing::writeText;

using testing::expectInputError;

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

/// A copy of `good` named `name` in the same folder, to be damaged.
fs::path copyBeside(const fs::path& good, const char* name) {
  const fs::path to = good.parent_path() / name;
  fs::copy_file(good, to);
  return to;
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
  auto copy = [&](const char* name) { return copyBeside(good, name); };
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

// A hand-damaged /refinement: marks that are not patches, round starts that do not run from 0
// to the marks' count. (That each mark is a patch of its round's mesh and that each round gives
// its recorded count is checked as the rounds are replayed: EndToEnd tests of --restart.)
TEST_F(CheckpointTest, DamagedRefinementRoundsAreNamed) {
  const int64_t np = 14;
  const fs::path good = dir_ / "rounds.h5";
  Checkpoint mine = myPart(np);
  mine.refinement.add({3, 1, 4}, 20);
  mine.refinement.add({}, 20);
  mine.refinement.add({5, 0}, 26);
  mine.refinement.addMerges({9, 2});
  writeCheckpoint(MPI_COMM_WORLD, good.string(), mine);
  auto copy = [&](const char* name) { return copyBeside(good, name); };
  if (worldRank() == 0) {
    rewrite<int64_t>(copy("negative_merge.h5"), "/refinement/merged", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[0] = -9; });
    rewrite<int64_t>(copy("merges_short.h5"), "/refinement/merged_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v.back() = 1; });
    rewrite<int64_t>(copy("negative_mark.h5"), "/refinement/marked", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[1] = -2; });
    rewrite<int64_t>(copy("starts_down.h5"), "/refinement/round_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[1] = v[2] + 1; });
    rewrite<int64_t>(copy("starts_short.h5"), "/refinement/round_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v.back() -= 1; });
    rewrite<int64_t>(copy("starts_late.h5"), "/refinement/round_start", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v.front() = 1; });
  }
  MPI_Barrier(MPI_COMM_WORLD);
  for (const char* name :
       {"negative_mark.h5", "starts_down.h5", "starts_short.h5", "starts_late.h5"}) {
    const std::string path = (dir_ / name).string();
    const std::string what = std::string(name).rfind("negative", 0) == 0
                                 ? "/refinement/marked holds -2"
                                 : "/refinement/round_start does not run from 0 to 5";
    expectInputError([&] { readCheckpointRefinement(MPI_COMM_WORLD, path); },
                     {name, "corrupt", what});
    expectInputError([&] { readCheckpoint(MPI_COMM_WORLD, path, 0, np); }, {name, what});
  }
  for (const auto& [name, what] :
       {std::pair{"negative_merge.h5", "/refinement/merged holds -9"},
        std::pair{"merges_short.h5", "/refinement/merged_start does not run from 0 to 2"}}) {
    const std::string path = (dir_ / name).string();
    expectInputError([&] { readCheckpointRefinement(MPI_COMM_WORLD, path); },
                     {name, "corrupt", what});
  }
  EXPECT_EQ(readCheckpointRefinement(MPI_COMM_WORLD, good.string()).merges(2),
            (std::vector<int64_t>{9, 2}));
  EXPECT_EQ(readCheckpointRefinement(MPI_COMM_WORLD, good.string()).rounds(), 3);
}

// A mesh whose triangles name no vertex, or whose coordinates are not finite, is damage, named.
TEST_F(CheckpointTest, DamagedMeshIsNamed) {
  const fs::path good = dir_ / "mesh.h5";
  Checkpoint mine = myPart(2);
  const CheckpointMesh mesh{
      "input", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2}}, {0, 0}};
  mine.mesh = viewOf(mesh);
  writeCheckpoint(MPI_COMM_WORLD, good.string(), mine);
  auto copy = [&](const char* name) { return copyBeside(good, name); };
  if (worldRank() == 0) {
    rewrite<int64_t>(copy("corner.h5"), "/mesh/triangles", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[4] = 4; });
    rewrite<double>(copy("nan.h5"), "/mesh/vertices", H5T_NATIVE_DOUBLE,
                    [](std::vector<double>& v) { v[7] = std::nan(""); });
    rewrite<int64_t>(copy("face.h5"), "/mesh/source_face", H5T_NATIVE_INT64,
                     [](std::vector<int64_t>& v) { v[1] = -1; });
  }
  MPI_Barrier(MPI_COMM_WORLD);
  for (auto [name, what] : {std::pair{"corner.h5", "/mesh/triangles row 1 names vertex 4 of 4"},
                            {"nan.h5", "/mesh/vertices row 2 is not finite"},
                            {"face.h5", "/mesh/source_face holds -1"}}) {
    const std::string path = (dir_ / name).string();
    expectInputError([&] { readCheckpointMesh(MPI_COMM_WORLD, path); }, {name, "corrupt", what});
  }
  EXPECT_EQ(readCheckpointMesh(MPI_COMM_WORLD, good.string()).triangles.size(), 2u);
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
