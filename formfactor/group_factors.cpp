#include "formfactor/group_factors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace radiosity::formfactor {

namespace {

/// The closed forms' quadrature error relative to a group factor, where the two estimates of a
/// pair cannot show it (mirror-image pairs compute the same sums both ways): against the exact
/// rectangle factors of the unit cube cut into squares, RMS 0.5e-6 to 3e-6 of the factor with
/// 4 × 4 squares a face, 1e-7 with 2 × 2 (docs/view3d.md): a bound of the right order.
constexpr double kClosedFormRelativeError = 1e-6;

// The group fluxes of rows added piece by piece, then combined (groupFactors).
class GroupTable {
 public:
  explicit GroupTable(const Mesh& patches)
      : patches_(patches),
        groups_(patches.labelNames.size()),
        area_(groups_, 0),
        squares_(groups_, 0),
        flux_(groups_ * groups_, 0),
        variance_(groups_ * groups_, 0),
        toGroup_(groups_, 0) {
    double total = 0;
    for (int64_t t = 0; t < patches.triangleCount(); ++t) {
      const double a = patches.area(t);
      const auto g = static_cast<size_t>(patches.label[t]);
      area_[g] += a;
      squares_[g] += a * a;
      total += a;
    }
    // Fluxes A_i Σ_{j∈b} F_ij in units of 2^-58 of the total area: every rank rounds its rows'
    // the same way, and integers add up exactly in any order. Rows sum to about 1 (MIS rows can
    // exceed it a little), so the sum of all fluxes stays far below 2^63 units.
    unit_ = std::ldexp(total, -58);
  }

  void add(const SampleTally& rows) {
    for (int64_t r = 0; r < rows.rowCount(); ++r) {
      for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k)
        addToGroup(rows.column[k], rows.sum[k]);
      finishRow(rows.firstRow + r, rows.samples);
    }
  }

  /// The same from F's one store as it is, the sums rebuilt from the values entry by entry (as
  /// SplitRows::tally does, without the tally: its entries in column order cost a copy of F a
  /// few thousand rows at a time, a second on 10^5 patches). A row's sums per group are
  /// integers: the order its entries come in does not matter.
  void add(const SplitRows& rows) {
    pairsOnce_ = rows.pairsOnce;  // (their diagonal slots hold 0: the rest is beside them)
    for (int64_t r = 0; r < rows.rowCount(); ++r) {
      const SplitRows::Block& diagonal = rows.diagonalBlock;
      for (int64_t k = diagonal.rowStart[r]; k < diagonal.rowStart[r + 1]; ++k)
        if (const double value = diagonal.at(k); value != 0)  // (not the explicit zero)
          addToGroup(rows.firstRow + diagonal.column[k], sumFromValue(value, rows.samples));
      const SplitRows::Block& other = rows.offDiagonalBlock;
      for (int64_t k = other.rowStart[r]; k < other.rowStart[r + 1]; ++k)
        if (const double value = other.at(k); value != 0)
          addToGroup(rows.offDiagonalColumn(k), sumFromValue(value, rows.samples));
      finishRow(rows.firstRow + r, rows.samples);
    }
  }

  GroupFactors combine(MPI_Comm comm, double areaScale, bool exactRows) {
    MPI_Allreduce(MPI_IN_PLACE, flux_.data(), static_cast<int>(flux_.size()), MPI_INT64_T, MPI_SUM,
                  comm);
    MPI_Allreduce(MPI_IN_PLACE, variance_.data(), static_cast<int>(variance_.size()), MPI_DOUBLE,
                  MPI_SUM, comm);
    const double scale = exactRows ? 0 : modelScale();
    GroupFactors result;
    result.names = patches_.labelNames;
    result.area = area_;
    for (double& a : result.area) a *= areaScale;
    result.factors.assign(groups_ * groups_, 0);
    result.factorError.assign(groups_ * groups_, 0);
    for (size_t a = 0; a < groups_; ++a) {
      if (area_[a] <= 0) continue;
      for (size_t b = 0; b < groups_; ++b) {
        const double mean_a = squares_[a] / area_[a];
        const double mean_b = area_[b] > 0 ? squares_[b] / area_[b] : 0;
        const double forward = static_cast<double>(flux_[a * groups_ + b]);
        const double backward = static_cast<double>(flux_[b * groups_ + a]);
        // Each estimate weighted by the other's variance.
        const double combined =
            a == b ? forward : (mean_b * forward + mean_a * backward) / (mean_a + mean_b);
        result.factors[a * groups_ + b] = combined * unit_ / area_[a];
        // The combined flux's variance: each estimate's model variance times the scale, by the
        // square of its weight (in fixed-point units, as the fluxes).
        const double wForward = a == b ? 1 : mean_b / (mean_a + mean_b);
        const double wBackward = 1 - wForward;
        const double unit2 = unit_ * unit_;
        const double variance =
            scale * (wForward * wForward * variance_[a * groups_ + b] / unit2 +
                     (a == b ? 0 : wBackward * wBackward * variance_[b * groups_ + a] / unit2));
        const double closedFormError =
            exactRows ? std::abs(forward - backward) / 2 + kClosedFormRelativeError * combined : 0;
        result.factorError[a * groups_ + b] =
            (std::sqrt(variance) + closedFormError) * unit_ / area_[a];
      }
    }
    return result;
  }

  /// What the binomial model's variances are worth here: the mean over the pairs of groups of
  /// (forward − backward)² / (V_forward + V_backward), one pair's worth shrunk towards 1.
  double modelScale() const {
    double sum = 1, pairs = 1;
    for (size_t a = 0; a < groups_; ++a) {
      for (size_t b = a + 1; b < groups_; ++b) {
        const double model =
            (variance_[a * groups_ + b] + variance_[b * groups_ + a]) / (unit_ * unit_);
        if (!(model > 0)) continue;
        const double difference = static_cast<double>(flux_[a * groups_ + b]) -
                                  static_cast<double>(flux_[b * groups_ + a]);
        sum += difference * difference / model;
        pairs += 1;
      }
    }
    return sum / pairs;
  }

 private:
  void addToGroup(int64_t column, int64_t sum) {
    const auto b = static_cast<size_t>(patches_.label[column]);
    if (toGroup_[b] == 0) reached_.push_back(b);
    toGroup_[b] += sum;
  }

  // Row i's sums per group (toGroup_) into the fluxes and the model's variances.
  void finishRow(int64_t i, int64_t samples) {
    const double perSum = 1.0 / (0x1p32 * static_cast<double>(samples));
    const auto a = static_cast<size_t>(patches_.label[i]);
    const double area = patches_.area(i);
    const double weight = area * perSum / unit_;
    const double perSample = area * area / static_cast<double>(samples);
    for (size_t b : reached_) {
      const int64_t flux = std::llround(weight * static_cast<double>(toGroup_[b]));
      flux_[a * groups_ + b] += flux;
      if (pairsOnce_) flux_[b * groups_ + a] += flux;  // the mirrors: A_j F_ji = A_i F_ij
      const double share = perSum * static_cast<double>(toGroup_[b]);  // Σ_{j∈b} F_ij
      variance_[a * groups_ + b] += perSample * share * std::max(0.0, 1 - share);
      toGroup_[b] = 0;
    }
    reached_.clear();
  }

  const Mesh& patches_;
  size_t groups_;
  std::vector<double> area_, squares_;
  double unit_ = 0;
  std::vector<int64_t> flux_;
  /// Per pair, Σ_{i∈a} A_i² p(1 − p)/N: the binomial model of the forward flux's variance.
  std::vector<double> variance_;
  // A row's sums per group it reaches (the groups in `reached_`, the rest of toGroup_ zero): a
  // row touches few groups, and a pass over all of them per row would cost rows × groups.
  std::vector<int64_t> toGroup_;
  std::vector<size_t> reached_;
  bool pairsOnce_ = false;
};

// One label too: a single surface's factor to itself is its closure, and a thermal run's heat
// rate goes with the table (/groups/heat_rate, export --groups-csv).
bool tabled(const Mesh& patches) {
  const size_t groups = patches.labelNames.size();
  return patches.hasLabels() && groups >= 1 && groups <= kMaxGroups;
}

}  // namespace

GroupFactors groupFactors(MPI_Comm comm, const Mesh& patches, const SampleTally& rows,
                          double areaScale, bool exactRows) {
  if (!tabled(patches)) return {};
  GroupTable table(patches);
  table.add(rows);
  return table.combine(comm, areaScale, exactRows);
}

GroupFactors groupFactors(MPI_Comm comm, const Mesh& patches, const SplitRows& rows,
                          double areaScale, bool exactRows) {
  if (!tabled(patches)) return {};
  GroupTable table(patches);
  if (rows.keptSums.rowCount() > 0 && !rows.pairsOnce) {  // the sums as sampled (2^18 samples+)
    table.add(rows.tally(0, rows.rowCount()));
  } else {
    table.add(rows);
  }
  return table.combine(comm, areaScale, exactRows);
}

std::vector<double> groupAreas(const Mesh& patches) {
  if (!tabled(patches)) return {};
  std::vector<double> area(patches.labelNames.size(), 0.0);
  for (int64_t t = 0; t < patches.triangleCount(); ++t)
    area[static_cast<size_t>(patches.label[t])] += patches.area(t);
  return area;
}

}  // namespace radiosity::formfactor
