// The exact tally behind rows of F stored as values (SplitRows), rebuilt a piece at a time.
#include "core/matrix_rows.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

namespace radiosity {

namespace {

// The whole pages of elements [0, count) of `data` back to the system (MADV_DONTNEED: they read
// as zeros if touched again). Pages shared with elements beyond `count` stay.
template <class T>
void releasePrefix(std::vector<T>& data, int64_t count) {
  count = std::min(count, static_cast<int64_t>(data.size()));  // never past the array's end
  static const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<uintptr_t>(data.data());
  const uintptr_t from = (begin + page - 1) / page * page,
                  to = (begin + static_cast<uintptr_t>(count) * sizeof(T)) / page * page;
  // Advice: where it fails the pages stay, which costs memory and nothing else.
  if (count > 0 && to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_DONTNEED);
}

void checkNotReleased(int64_t from, int64_t released) {
  if (from < released)
    throw std::logic_error("rows of F read after they were given back (row " +
                           std::to_string(from) + " of the first " + std::to_string(released) +
                           ")");
}

}  // namespace

void SampleTally::releaseRowsBefore(int64_t row) {
  if (row <= releasedRows) return;
  releasePrefix(column, rowStart[row]);
  releasePrefix(sum, rowStart[row]);
  releasedRows = row;
}

void SplitRows::releaseRowsBefore(int64_t row) {
  if (row <= releasedRows) return;
  for (Block* block : {&diagonalBlock, &offDiagonalBlock}) {
    releasePrefix(block->column, block->rowStart[row]);
    releasePrefix(block->value, block->rowStart[row]);
    releasePrefix(block->singleValue, block->rowStart[row]);
  }
  if (keptSums.rowCount() > 0) keptSums.releaseRowsBefore(row);
  releasedRows = row;
}

SampleTally SampleTally::slice(int64_t from, int64_t to, int64_t samplesBehind) const {
  checkNotReleased(from, releasedRows);
  SampleTally part;
  part.firstRow = firstRow + from;
  part.samples = samplesBehind;
  const int64_t begin = rowStart[from], end = rowStart[to];
  part.column.assign(column.begin() + begin, column.begin() + end);
  part.sum.assign(sum.begin() + begin, sum.begin() + end);
  part.rowStart.clear();
  for (int64_t r = from; r <= to; ++r) part.rowStart.push_back(rowStart[r] - begin);
  return part;
}

SampleTally SplitRows::tally(int64_t from, int64_t to) const {
  checkNotReleased(from, releasedRows);
  if (keptSums.rowCount() > 0) {  // the sums as sampled
    SampleTally part = keptSums.slice(from, to, samples);
    part.firstRow = firstRow + from;
    return part;
  }
  SampleTally part;
  part.firstRow = firstRow + from;
  part.samples = samples;
  for (int64_t r = from; r < to; ++r) {
    forEachInColumnOrder(r, [&](int64_t column, double value) {
      if (value == 0) return;  // the explicit zero diagonal
      part.column.push_back(column);
      part.sum.push_back(sumFromValue(value, samples));
    });
    part.rowStart.push_back(static_cast<int64_t>(part.column.size()));
  }
  return part;
}

SparseRows SplitRows::values(int64_t from, int64_t to) const {
  checkNotReleased(from, releasedRows);
  if (pairsOnce)
    throw std::logic_error(
        "rows stored once a pair read as F's rows (their diagonal holds the "
        "others' sum)");
  SparseRows part;
  part.firstRow = firstRow + from;
  // Counted first: arrays of F's size grown by doubling would hold up to twice it, and a move.
  int64_t count = 0;
  for (int64_t r = from; r < to; ++r)
    forEachInColumnOrder(r, [&](int64_t, double value) { count += value != 0 ? 1 : 0; });
  part.column.reserve(static_cast<size_t>(count));
  part.value.reserve(static_cast<size_t>(count));
  for (int64_t r = from; r < to; ++r) {
    forEachInColumnOrder(r, [&](int64_t column, double value) {
      if (value == 0) return;  // the explicit zero diagonal
      part.column.push_back(column);
      part.value.push_back(value);
    });
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
        count += block->at(k) != 0 ? 1 : 0;
    if (pairsOnce && pairRest[static_cast<size_t>(r)] != 0) ++count;  // (its slot holds 0)
    start[r + 1] = start[r] + count;
  }
  return start;
}

}  // namespace radiosity
