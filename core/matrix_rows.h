// Rows of the form-factor matrix as the stages hand them on: values (MatrixRows) and the exact
// sample sums behind them (TallyRows), and F summed over groups of patches (GroupFactors).
#pragma once

#include <cstdint>
#include <string>
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

/// View factors between groups of patches (the scene's labels: materials, OBJ groups, the
/// buildings of builtin:city), under /groups: F(a→b) = Σ_{i∈a} A_i Σ_{j∈b} F_ij / A_a. Written
/// with each patch's group, /patches/group (the mesh's labels), which readResult() gives back as
/// Mesh::label and labelNames.
struct GroupFactors {
  std::vector<std::string> names;  ///< attribute `names` of /groups/view_factors
  std::vector<double> area;        ///< /groups/area [G]: A_a, in the result's units
  std::vector<double> factors;     ///< /groups/view_factors [G,G], F(a→b) at a·G + b
  bool empty() const { return names.empty(); }
};

}  // namespace radiosity
