// Rows of the form-factor matrix as the stages hand them on: values (SparseRows), the exact
// sample sums behind them (SampleTally), the values as F's one store (SplitRows), and F summed over
// groups of patches (GroupFactors).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace radiosity {

/// Rows [firstRow, firstRow + rowCount()) of a sparse matrix in CSR form: row r holds the
/// columns column[rowStart[r] .. rowStart[r+1]) with their values; rowStart[0] = 0.
struct SparseRows {
  int64_t firstRow = 0;
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<double> value;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
  int64_t nonzeros() const { return static_cast<int64_t>(column.size()); }
};

/// Exact sample sums behind rows of F: row r (patch firstRow + r)
/// holds columns column[rowStart[r] .. rowStart[r+1]) with sum = Σ contributions · 2^32 over
/// `samples` samples, so that F_ij = sum / (2^32 · samples) and more samples simply add up.
struct SampleTally {
  int64_t firstRow = 0;
  int64_t samples = 0;  ///< samples per row behind the sums
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<int64_t> sum;
  /// Rows before this one (counted from firstRow) were given back (releaseRowsBefore).
  int64_t releasedRows = 0;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
  /// Rows [from, to) (counted from firstRow) as a tally of their own, over `samplesBehind`.
  /// Throws std::logic_error for a row given back.
  SampleTally slice(int64_t from, int64_t to, int64_t samplesBehind) const;
  /// Gives the memory of rows [0, row) back to the system while the arrays stay where they are:
  /// an extended copy of the rows is being filled beside them (a rays round, a restart), and
  /// they are read in order, once. Their pages read as zeros from here on.
  void releaseRowsBefore(int64_t row);
};

/// The sum behind F_ij = value over `samples` samples: value · 2^32 · samples rounded, exact for
/// every sum below about 2^50 (two roundings of 2^-53 each), which callers check, not assume.
inline int64_t sumFromValue(double value, int64_t samples) {
  return std::llround(value * (0x1p32 * static_cast<double>(samples)));
}

/// This rank's rows [firstRow, firstRow + rowCount()) of F as values, in the two blocks a
/// distributed sparse matrix keeps (PETSc's MPIAIJ), so that the solve lends the arrays to PETSc
/// instead of copying them (or, in single precision, multiplies by them itself:
/// solve/single_precision_matrix.h), and 32-bit indices (PETSc's here): the one store of F from
/// the form-factor stage to the end of the run, 12 bytes a nonzero (8 in single precision). Each
/// double value is sum / (2^32 · samples) of the tally it came from and gives that sum back
/// (sumFromValue; checked as rows are appended), so the tally a checkpoint stores is rebuilt from
/// it a piece at a time (tally()); a single value gives its rounded sum back.
struct SplitRows {
  /// One block in CSR form: row r holds column[rowStart[r] .. rowStart[r+1]) with their values.
  struct Block {
    std::vector<int32_t> rowStart{0};
    std::vector<int32_t> column;
    std::vector<double> value;       ///< in double precision, or...
    std::vector<float> singleValue;  ///< ...in single (SplitRows::singlePrecision), 8 B a nonzero
    bool single = false;             ///< which of the two holds the values
    double at(int64_t k) const {
      return single ? singleValue[static_cast<size_t>(k)] : value[static_cast<size_t>(k)];
    }
  };
  int64_t firstRow = 0;
  /// The rows the store is for end here (rowCount() tells how many are in so far): the rank's
  /// rows, whose columns [firstRow, endRow) make the diagonal block.
  int64_t endRow = 0;
  int64_t samples = 0;  ///< samples per row behind the values
  /// The values in single precision (set before the first row goes in): 8 B a nonzero instead of
  /// 12, where the rounding (2^-24 of each value) is far below the sampling error
  /// (formfactor::singlePrecisionServes). The tally rebuilt from them is then their rounded
  /// sums: the same on any rank count and through any checkpoint, but no longer the one sampled.
  bool singlePrecision = false;
  /// The columns [firstRow, endRow), counted from firstRow; every row holds its diagonal
  /// entry, an explicit zero unless sampled (room for the solvers' shifts).
  Block diagonalBlock;
  /// The other columns, as global patch ids, ascending in each row.
  Block offDiagonalBlock;
  /// While PETSc holds the blocks it numbers offDiagonalBlock's columns compactly: the global id
  /// of entry k is then columnMap[column[k]] (PETSc's array). Null otherwise.
  const int32_t* columnMap = nullptr;
  /// Exact rows stored once a pair (formfactor::ownsPair): each row holds the F_ij of the pairs it
  /// owns, and pairRest its diagonal entry: the sum of its others (F_ji A_j / A_i of the rows
  /// that own them, to the closed forms' agreement), so that a row's entries still add up to its
  /// sum and its tally stands alone. Only the solve's shell reads such rows as F
  /// (solve/single_precision_matrix.h); values() refuses them.
  bool pairsOnce = false;
  std::vector<double> pairRest;  ///< per row, with pairsOnce: its diagonal entry, exactly
  /// The tally itself, kept only where the values cannot give it back (rows of 2^18 samples or
  /// more: formfactor::kExactSumSamples); empty otherwise.
  SampleTally keptSums;
  int64_t entries = 0;  ///< entries of the tallies appended (the explicit zeros not counted)

  int64_t rowCount() const { return static_cast<int64_t>(diagonalBlock.rowStart.size()) - 1; }
  int64_t offDiagonalColumn(int64_t k) const {
    const int32_t j = offDiagonalBlock.column[static_cast<size_t>(k)];
    return columnMap ? columnMap[j] : j;
  }
  /// Rows before this one were given back (releaseRowsBefore).
  int64_t releasedRows = 0;
  /// Rows [from, to) (counted from firstRow) as the tally they came from: their entries with a
  /// value other than 0, in column order, each sum rebuilt exactly (or taken from keptSums).
  /// Throws std::logic_error for a row given back.
  SampleTally tally(int64_t from, int64_t to) const;
  /// As SampleTally::releaseRowsBefore: the rows' entries in both blocks (and keptSums) go back to
  /// the system, the arrays stay; a store lent to PETSc must not be given back.
  void releaseRowsBefore(int64_t row);
  /// The tally's row starts, rowStart[0] = 0, for every row: a pass over the values.
  std::vector<int64_t> tallyRowStart() const;
  /// Rows [from, to) (counted from firstRow) as F's values: the entries tally() gives, with their
  /// values, so that tallyRowStart() lays them out (the result's /formfactors written a piece at
  /// a time from the store, without a copy of F). Throws std::logic_error for a row given back.
  SparseRows values(int64_t from, int64_t to) const;

  /// Calls visit(column, value) for row r's stored entries in column order (the off-diagonal
  /// ones before the rank's own block, the block, the rest), the explicit zero diagonal too.
  template <class Visit>
  void forEachInColumnOrder(int64_t r, Visit&& visit) const {
    const int64_t row = firstRow + r;
    int64_t k = offDiagonalBlock.rowStart[r];
    const int64_t kEnd = offDiagonalBlock.rowStart[r + 1];
    for (; k < kEnd && offDiagonalColumn(k) < row; ++k)
      visit(offDiagonalColumn(k), offDiagonalBlock.at(k));
    for (int64_t d = diagonalBlock.rowStart[r]; d < diagonalBlock.rowStart[r + 1]; ++d) {
      const int64_t column = diagonalBlock.column[d];
      visit(firstRow + column,
            pairsOnce && column == r ? pairRest[static_cast<size_t>(r)] : diagonalBlock.at(d));
    }
    for (; k < kEnd; ++k) visit(offDiagonalColumn(k), offDiagonalBlock.at(k));
  }
};

/// View factors between groups of patches (the scene's labels: materials, OBJ groups, the
/// buildings of builtin:city), under /groups: F(a→b) = Σ_{i∈a} A_i Σ_{j∈b} F_ij / A_a. Written
/// with each patch's group, /patches/group (the mesh's labels), which readResult() gives back as
/// Mesh::label and labelNames.
struct GroupFactors {
  std::vector<std::string> names;  ///< attribute `names` of /groups/view_factors
  std::vector<double> area;        ///< /groups/area [G]: A_a, in the result's units
  std::vector<double> factors;     ///< /groups/view_factors [G,G], F(a→b) at a·G + b
  /// /groups/view_factor_error [G,G]: the estimated standard error of each factor (same
  /// layout); empty in results written before it existed.
  std::vector<double> factorError;
  /// A thermal run's net heat rate leaving each group, W: /groups/heat_rate [G]; empty: none.
  std::vector<double> heatRate;
  std::vector<double> heatRateError;  ///< its estimated error, W: /groups/heat_rate_error
  bool empty() const { return names.empty(); }
};

}  // namespace radiosity
