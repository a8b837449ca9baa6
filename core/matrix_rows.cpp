// The exact tally behind rows of F stored as values (SplitRows), rebuilt a piece at a time.
#include "core/matrix_rows.h"

namespace radiosity {

TallyRows TallyRows::slice(int64_t from, int64_t to, int64_t samplesBehind) const {
  TallyRows part;
  part.firstRow = firstRow + from;
  part.samples = samplesBehind;
  const int64_t begin = rowStart[from], end = rowStart[to];
  part.column.assign(column.begin() + begin, column.begin() + end);
  part.sum.assign(sum.begin() + begin, sum.begin() + end);
  part.rowStart.clear();
  for (int64_t r = from; r <= to; ++r) part.rowStart.push_back(rowStart[r] - begin);
  return part;
}

TallyRows SplitRows::tally(int64_t from, int64_t to) const {
  if (keptSums.rowCount() > 0) {  // the sums as sampled
    TallyRows part = keptSums.slice(from, to, samples);
    part.firstRow = firstRow + from;
    return part;
  }
  TallyRows part;
  part.firstRow = firstRow + from;
  part.samples = samples;
  const Block& own = diagonalBlock;
  const Block& other = offDiagonalBlock;
  auto add = [&](int64_t column, double value) {
    if (value == 0) return;  // the explicit zero diagonal
    part.column.push_back(column);
    part.sum.push_back(sumFromValue(value, samples));
  };
  for (int64_t r = from; r < to; ++r) {
    const int64_t row = firstRow + r;
    int64_t k = other.rowStart[r];
    const int64_t kEnd = other.rowStart[r + 1];
    for (; k < kEnd && offDiagonalColumn(k) < row; ++k) add(offDiagonalColumn(k), other.value[k]);
    for (int64_t d = own.rowStart[r]; d < own.rowStart[r + 1]; ++d)
      add(firstRow + own.column[d], own.value[d]);
    for (; k < kEnd; ++k) add(offDiagonalColumn(k), other.value[k]);
    part.rowStart.push_back(static_cast<int64_t>(part.column.size()));
  }
  return part;
}

std::vector<int64_t> SplitRows::tallyRowStart() const {
  if (keptSums.rowCount() > 0) return keptSums.rowStart;
  std::vector<int64_t> start(static_cast<size_t>(rowCount()) + 1, 0);
  for (int64_t r = 0; r < rowCount(); ++r) {
    int64_t count = 0;
    for (const Block* block : {&diagonalBlock, &offDiagonalBlock})
      for (int64_t k = block->rowStart[r]; k < block->rowStart[r + 1]; ++k)
        count += block->value[k] != 0 ? 1 : 0;
    start[r + 1] = start[r] + count;
  }
  return start;
}

}  // namespace radiosity
