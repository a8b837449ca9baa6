// Rows of the form-factor matrix as the stages hand them on: values (MatrixRows) and the exact
// sample sums behind them (TallyRows).
#pragma once

#include <cstdint>
#include <vector>

namespace radiosity {

/// Rows [firstRow, firstRow + rowCount()) of a sparse matrix in CSR form: row r holds the
/// columns column[rowStart[r] .. rowStart[r+1]) with their values; rowStart[0] = 0.
struct MatrixRows {
  int64_t firstRow = 0;
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<double> value;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
  int64_t nonzeros() const { return static_cast<int64_t>(column.size()); }
};

/// Exact sample sums behind rows of F (formfactor's SampleTally): row r (patch firstRow + r)
/// holds columns column[rowStart[r] .. rowStart[r+1]) with sum = Σ contributions · 2^32 over
/// `samples` samples, so that F_ij = sum / (2^32 · samples) and more samples simply add up.
struct TallyRows {
  int64_t firstRow = 0;
  int64_t samples = 0;  ///< samples per row behind the sums
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<int64_t> sum;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
};

}  // namespace radiosity
