// What the checkpoint-file tests (io_checkpoint_*_test.cpp) share: a made-up checkpoint of np
// patches dealt to the ranks in blocks, its comparison with what is read back, and a fresh
// directory per test.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/store/checkpoint.h"
#include "mpi_environment.h"
#include "temp_dir.h"

namespace radiosity::testing {

/// The first row of `rank` of `size` when np rows are dealt in contiguous blocks.
inline int64_t blockStart(int64_t np, int rank, int size) { return np * rank / size; }

/// The samples of row i of a made-up checkpoint: rows i % 4 == 1 are not sampled yet, the
/// others have 1024 samples.
inline int64_t samplesOf(int64_t i) { return i % 4 != 1 ? 1024 : 0; }

/// Mixed samples, as a restart with more rays leaves them: rows i % 5 == 0 not sampled, rows
/// i % 5 == 1 or 2 with 256 samples, the others with 1024.
inline int64_t mixedSamplesOf(int64_t i) {
  const int64_t k = i % 5;
  return k == 0 ? 0 : k <= 2 ? 256 : 1024;
}

inline SolveHistory someHistory() {
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
inline Checkpoint partOf(int64_t np, int64_t first, int64_t end,
                         int64_t (*samples)(int64_t) = samplesOf) {
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
    c.rowBalance.push_back(1 + 1.0 / static_cast<double>(i + 7));
  }
  return c;
}

/// This rank's block of the made-up checkpoint.
inline Checkpoint myPart(int64_t np, int64_t (*samples)(int64_t) = samplesOf) {
  return partOf(np, blockStart(np, worldRank(), worldSize()),
                blockStart(np, worldRank() + 1, worldSize()), samples);
}

/// `a` (read back) holds what `b` (written, or made up alike) does. rows.samples is not part of
/// a checkpoint: the reader sets it to the largest of its rowSamples, 0 if it has no rows.
inline void expectSame(const Checkpoint& a, const Checkpoint& b) {
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
  EXPECT_EQ(a.rowBalance, b.rowBalance);
  EXPECT_EQ(a.progress.history.channel, b.progress.history.channel);
  EXPECT_EQ(a.progress.history.iteration, b.progress.history.iteration);
  EXPECT_EQ(a.progress.history.residual, b.progress.history.residual);
  EXPECT_EQ(a.progress.history.seconds, b.progress.history.seconds);
  EXPECT_EQ(a.rows.rowsFinished(), b.rows.rowsFinished());
}

inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Each test gets a fresh directory, the same on every rank.
class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_FALSE(dir_.empty()); }

  radiosity::testing::SharedTempDir temp_{"io_checkpoint_test"};
  std::filesystem::path dir_ = temp_.path();
};

}  // namespace radiosity::testing
