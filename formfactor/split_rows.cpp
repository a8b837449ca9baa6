// Rows of F appended to its one store (SplitRows) as they are sampled, and read back from it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

namespace {

constexpr int64_t kIndexLimit = std::numeric_limits<int32_t>::max();

void checkIndexes(const SplitRows& rows, const SampleTally& piece) {
  const int64_t lastRow = piece.firstRow + piece.rowCount();
  const auto entries = [](const SplitRows::Block& b) {
    return static_cast<int64_t>(b.column.size());
  };
  const int64_t most =
      std::max(entries(rows.diagonalBlock) + piece.rowCount(), entries(rows.offDiagonalBlock)) +
      static_cast<int64_t>(piece.column.size());
  int64_t lastColumn = lastRow;
  for (int64_t j : piece.column) lastColumn = std::max(lastColumn, j + 1);
  if (lastColumn > kIndexLimit || most > kIndexLimit) {
    throw Error(exit_code::kUsage,
                "F does not fit the solver's 32-bit indices: " + std::to_string(lastColumn) +
                    " patches and up to " + std::to_string(most) +
                    " nonzeros on one rank, where 2^31 - 1 is the most; use more ranks (nonzeros) "
                    "or fewer patches");
  }
}

void push(SplitRows::Block& block, double value) {
  if (block.single) {
    block.singleValue.push_back(static_cast<float>(value));
  } else {
    block.value.push_back(value);
  }
}

}  // namespace

namespace {

// The piece's sums kept beside the values (rows of kExactSumSamples samples or more).
void keepBeside(SplitRows& rows, const SampleTally& piece) {
  SampleTally& kept = rows.keptSums;
  if (kept.rowCount() == 0) {
    kept.firstRow = rows.firstRow;
    kept.samples = rows.samples;
  }
  const auto base = static_cast<int64_t>(kept.column.size());
  kept.column.insert(kept.column.end(), piece.column.begin(), piece.column.end());
  kept.sum.insert(kept.sum.end(), piece.sum.begin(), piece.sum.end());
  for (int64_t r = 1; r <= piece.rowCount(); ++r) kept.rowStart.push_back(base + piece.rowStart[r]);
}

}  // namespace

void appendRows(SplitRows& rows, const SampleTally& piece) {
  if (rows.rowCount() == 0) {
    if (rows.endRow <= piece.firstRow) rows.endRow = piece.firstRow + piece.rowCount();
    rows.firstRow = piece.firstRow;
    rows.samples = piece.samples;
  }
  if (piece.firstRow + piece.rowCount() > rows.endRow) {
    throw Error(exit_code::kFailure, "appendRows: the piece ends past the rows the store is for");
  } else if (piece.firstRow != rows.firstRow + rows.rowCount() || piece.samples != rows.samples) {
    throw Error(exit_code::kFailure, "appendRows: the piece does not follow the rows stored");
  }
  checkIndexes(rows, piece);
  const bool single = rows.singlePrecision;
  if (single && piece.samples >= kExactSumSamples)
    throw Error(exit_code::kFailure,
                "appendRows: rows of 2^18 samples or more in single precision");
  rows.diagonalBlock.single = rows.offDiagonalBlock.single = single;
  const bool keepSums = piece.samples >= kExactSumSamples;
  const double scale = 0x1p-32 / static_cast<double>(piece.samples);
  SplitRows::Block& own = rows.diagonalBlock;
  SplitRows::Block& other = rows.offDiagonalBlock;
  const int64_t end = rows.endRow;
  for (int64_t r = 0; r < piece.rowCount(); ++r) {
    const int64_t row = piece.firstRow + r;
    bool diagonal = false;
    double rest = 0;  // (pairsOnce: the diagonal entry, kept exactly beside the slot's 0)
    for (int64_t k = piece.rowStart[r]; k < piece.rowStart[r + 1]; ++k) {
      const int64_t j = piece.column[k];
      const double value = piece.sum[k] * scale;
      if (!keepSums && !single && sumFromValue(value, piece.samples) != piece.sum[k])
        throw Error(exit_code::kFailure, "appendRows: F_" + std::to_string(row) + "," +
                                             std::to_string(j) + " loses its sum as a double");
      if (j >= row && !diagonal) {  // the diagonal, in its place: sampled or an explicit zero
        own.column.push_back(static_cast<int32_t>(row - rows.firstRow));
        if (j == row && rows.pairsOnce) rest = value;
        push(own, j == row && !rows.pairsOnce ? value : 0.0);
        diagonal = true;
        if (j == row) continue;
      }
      SplitRows::Block& block = j >= rows.firstRow && j < end ? own : other;
      block.column.push_back(static_cast<int32_t>(&block == &own ? j - rows.firstRow : j));
      push(block, value);
    }
    if (!diagonal) {
      own.column.push_back(static_cast<int32_t>(row - rows.firstRow));
      push(own, 0.0);
    }
    own.rowStart.push_back(static_cast<int32_t>(own.column.size()));
    other.rowStart.push_back(static_cast<int32_t>(other.column.size()));
    if (rows.pairsOnce) rows.pairRest.push_back(rest);
  }
  rows.entries += static_cast<int64_t>(piece.column.size());
  if (keepSums) keepBeside(rows, piece);
}

bool singlePrecisionServes(int64_t samples, double largestReflectance) {
  if (samples <= 0 || samples >= kExactSumSamples || !(largestReflectance < 1)) return false;
  const double rounding = 0x1p-24 / (1 - std::max(0.0, largestReflectance));
  return rounding <= 1e-3 * std::pow(static_cast<double>(samples), -2.0 / 3.0);
}

bool singlePrecisionServesExactRows(int64_t patches, int64_t samples) {
  return patches >= kSingleExactRowsPatches && samples > 0 && samples < kExactSumSamples;
}

void reserveRows(SplitRows& rows, int64_t expectedRows) {
  const int64_t have = rows.rowCount();
  if (have == 0 || expectedRows <= have) return;
  const double rowsAhead = static_cast<double>(expectedRows) / static_cast<double>(have);
  for (SplitRows::Block* block : {&rows.diagonalBlock, &rows.offDiagonalBlock}) {
    // Only when the estimate outgrows the room: every move to a larger array holds the old
    // and the new one while it copies (at 10^6 patches that moment was the run's peak), so the
    // room is twice the estimate. Room not yet filled is address space only: its pages become
    // resident as the rows fill them.
    const auto estimate =
        static_cast<size_t>(rowsAhead * static_cast<double>(block->column.size()));
    if (block->column.capacity() < estimate) {
      const auto entries = static_cast<size_t>(2 * static_cast<double>(estimate)) + 1024;
      block->column.reserve(entries);
      if (block->single) {
        block->singleValue.reserve(entries);
      } else {
        block->value.reserve(entries);
      }
    }
    block->rowStart.reserve(static_cast<size_t>(expectedRows) + 1);
  }
  if (rows.keptSums.rowCount() > 0) reserveRows(rows.keptSums, expectedRows);
}

SparseRows toFormFactors(const SplitRows& rows) { return rows.values(0, rows.rowCount()); }

std::vector<double> rowSums(const SplitRows& rows) {
  std::vector<double> sums(static_cast<size_t>(rows.rowCount()), 0.0);
  for (int64_t r = 0; r < rows.rowCount(); ++r)
    rows.forEachInColumnOrder(r, [&](int64_t, double value) { sums[r] += value; });
  return sums;
}

}  // namespace radiosity::formfactor
