#include "formfactor/group_factors.h"

#include <cmath>
#include <cstdint>

namespace radiosity::formfactor {

GroupFactors groupFactors(MPI_Comm comm, const Mesh& patches, const formfactor::SampleTally& rows,
                          double areaScale) {
  const size_t groups = patches.labelNames.size();
  if (!patches.hasLabels() || groups < 2 || groups > kMaxGroups) return {};
  std::vector<double> area(groups, 0), squares(groups, 0);
  double total = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const double a = patches.area(t);
    const auto g = static_cast<size_t>(patches.label[t]);
    area[g] += a;
    squares[g] += a * a;
    total += a;
  }
  // Fluxes A_i Σ_{j∈b} F_ij in units of 2^-58 of the total area: every rank rounds its rows'
  // the same way, and integers add up exactly in any order. Rows sum to about 1 (MIS rows can
  // exceed it a little), so the sum of all fluxes stays far below 2^63 units.
  const double unit = std::ldexp(total, -58);
  std::vector<int64_t> flux(groups * groups, 0);
  // A row's sums per group it reaches (the groups in `reached`, the rest of toGroup zero): a
  // row touches few groups, and a pass over all of them per row would cost rows × groups.
  std::vector<int64_t> toGroup(groups, 0);
  std::vector<size_t> reached;
  const double perSum = 1.0 / (0x1p32 * static_cast<double>(rows.samples));
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    const int64_t i = rows.firstRow + r;
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) {
      const auto b = static_cast<size_t>(patches.label[rows.column[k]]);
      if (toGroup[b] == 0) reached.push_back(b);
      toGroup[b] += rows.sum[k];
    }
    const auto a = static_cast<size_t>(patches.label[i]);
    const double weight = patches.area(i) * perSum / unit;
    for (size_t b : reached) {
      flux[a * groups + b] += std::llround(weight * static_cast<double>(toGroup[b]));
      toGroup[b] = 0;
    }
    reached.clear();
  }
  MPI_Allreduce(MPI_IN_PLACE, flux.data(), static_cast<int>(flux.size()), MPI_INT64_T, MPI_SUM,
                comm);
  GroupFactors result;
  result.names = patches.labelNames;
  result.area = area;
  for (double& a : result.area) a *= areaScale;
  result.factors.assign(groups * groups, 0);
  for (size_t a = 0; a < groups; ++a) {
    if (area[a] <= 0) continue;
    for (size_t b = 0; b < groups; ++b) {
      const double mean_a = squares[a] / area[a];
      const double mean_b = area[b] > 0 ? squares[b] / area[b] : 0;
      const double forward = static_cast<double>(flux[a * groups + b]);
      const double backward = static_cast<double>(flux[b * groups + a]);
      // Each estimate weighted by the other's variance.
      const double combined =
          a == b ? forward : (mean_b * forward + mean_a * backward) / (mean_a + mean_b);
      result.factors[a * groups + b] = combined * unit / area[a];
    }
  }
  return result;
}

}  // namespace radiosity::formfactor
