// A rank's rows as links and direct light (linked_rows.h).
#include "hierarchy/linked_rows.h"

#include <stdexcept>

namespace radiosity::hierarchy {

LinkedRows::LinkedRows(const PatchTree& tree, const LinkOracle& oracle, const Mesh& patches,
                       partition::PatchRange owned)
    : tally_(tree, oracle),
      patches_(patches),
      owned_(owned),
      direct_(static_cast<size_t>(owned.size()), Rgb{0, 0, 0}) {}

void LinkedRows::add(const SampleTally& piece) {
  if (piece.firstRow < owned_.begin || piece.firstRow + piece.rowCount() > owned_.end)
    throw std::logic_error("LinkedRows::add: rows outside the owned block");
  tally_.add(piece);
  const double unit = 0x1p32 * static_cast<double>(piece.samples);
  for (int64_t row = 0; row < piece.rowCount(); ++row) {
    const int64_t local = piece.firstRow + row - owned_.begin;
    for (int64_t k = piece.rowStart[row]; k < piece.rowStart[row + 1]; ++k) {
      const double f = static_cast<double>(piece.sum[k]) / unit;
      const Rgb& e = patches_.emission[piece.column[k]];
      for (int c = 0; c < 3; ++c) direct_[local][c] += f * e[c];
    }
  }
}

}  // namespace radiosity::hierarchy
