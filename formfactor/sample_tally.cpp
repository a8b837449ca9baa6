// Turning exact sample sums into form factors, adding sample sets, and summarising rows.
#include <algorithm>

#include "core/error.h"
#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

SparseRows toFormFactors(const SampleTally& tally) {
  SparseRows rows;
  rows.firstRow = tally.firstRow;
  rows.rowStart = tally.rowStart;
  rows.column = tally.column;
  rows.value.resize(tally.sum.size());
  const double scale = 0x1p-32 / static_cast<double>(tally.samples);
  for (size_t k = 0; k < tally.sum.size(); ++k) rows.value[k] = tally.sum[k] * scale;
  return rows;
}

bool valuesKeepTheSums(const SampleTally& tally) {
  const double scale = 0x1p-32 / static_cast<double>(tally.samples);
  for (int64_t sum : tally.sum)
    if (sumFromValue(sum * scale, tally.samples) != sum) return false;
  return true;
}

std::vector<double> rowSums(const SparseRows& rows) {
  std::vector<double> sums(rows.rowCount(), 0.0);
  for (int64_t r = 0; r < rows.rowCount(); ++r)
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) sums[r] += rows.value[k];
  return sums;
}

std::vector<double> rowSums(const SampleTally& tally) {
  const double scale = 0x1p-32 / static_cast<double>(tally.samples);
  std::vector<double> sums(tally.rowCount(), 0.0);
  for (int64_t r = 0; r < tally.rowCount(); ++r)
    for (int64_t k = tally.rowStart[r]; k < tally.rowStart[r + 1]; ++k)
      sums[r] += tally.sum[k] * scale;
  return sums;
}

SampleTally mergeSamples(const SampleTally& a, const SampleTally& b) {
  if (a.firstRow != b.firstRow || a.rowCount() != b.rowCount()) {
    throw Error(exit_code::kFailure, "mergeSamples: the two tallies hold different rows");
  }
  SampleTally merged;
  merged.firstRow = a.firstRow;
  merged.samples = a.samples + b.samples;
  for (int64_t r = 0; r < a.rowCount(); ++r) {
    int64_t i = a.rowStart[r], j = b.rowStart[r];
    const int64_t iEnd = a.rowStart[r + 1], jEnd = b.rowStart[r + 1];
    while (i < iEnd || j < jEnd) {
      if (j == jEnd || (i < iEnd && a.column[i] < b.column[j])) {
        merged.column.push_back(a.column[i]);
        merged.sum.push_back(a.sum[i++]);
      } else if (i == iEnd || b.column[j] < a.column[i]) {
        merged.column.push_back(b.column[j]);
        merged.sum.push_back(b.sum[j++]);
      } else {
        merged.column.push_back(a.column[i]);
        merged.sum.push_back(a.sum[i++] + b.sum[j++]);
      }
    }
    merged.rowStart.push_back(static_cast<int64_t>(merged.column.size()));
  }
  return merged;
}

void reserveRows(SampleTally& tally, int64_t expectedRows) {
  const int64_t have = tally.rowCount();
  if (have == 0 || expectedRows <= have) return;
  const double perRow = static_cast<double>(tally.column.size()) / static_cast<double>(have);
  const auto estimate = static_cast<size_t>(perRow * static_cast<double>(expectedRows));
  if (tally.column.capacity() < estimate) {
    const auto entries = static_cast<size_t>(1.25 * static_cast<double>(estimate)) + 1024;
    tally.column.reserve(entries);
    tally.sum.reserve(entries);
  }
  tally.rowStart.reserve(static_cast<size_t>(expectedRows) + 1);
}

const std::vector<double>& rowSumBinEdges() {
  static const std::vector<double> edges = {0.0, 0.5, 0.9, 0.99, 0.999, 1 - 1e-9, 1 + 1e-9};
  return edges;
}

void addRowSums(const SparseRows& rows, Statistics& statistics) {
  addRowSums(rowSums(rows), statistics);
}

void addRowSums(const std::vector<double>& rowSums, Statistics& statistics) {
  for (double sum : rowSums) {
    statistics.minRowSum = std::min(statistics.minRowSum, sum);
    statistics.maxRowSum = std::max(statistics.maxRowSum, sum);
    statistics.sumRowSums += sum;
  }
}

std::vector<int64_t> rowSumHistogram(const SparseRows& rows) {
  return rowSumHistogram(rowSums(rows));
}

std::vector<int64_t> rowSumHistogram(const std::vector<double>& rowSums) {
  const std::vector<double>& edges = rowSumBinEdges();
  std::vector<int64_t> counts(edges.size(), 0);  // last bin: above 1 + 1e-9
  for (double sum : rowSums) {
    // The bin of the last edge ≤ sum, except that [1 − 1e-9, 1 + 1e-9] is closed on the right.
    size_t bin = std::upper_bound(edges.begin(), edges.end(), sum) - edges.begin();
    bin = bin == 0 ? 0 : bin - 1;
    if (sum == edges.back()) bin = edges.size() - 2;
    ++counts[bin];
  }
  return counts;
}

}  // namespace radiosity::formfactor
