#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "partition/partition.h"

namespace radiosity::partition {

PatchRange blockOf(int64_t count, int rank, int ranks) {
  int64_t base = count / ranks, extra = count % ranks;
  int64_t begin = rank * base + std::min<int64_t>(rank, extra);
  return {begin, begin + base + (rank < extra ? 1 : 0)};
}

int ownerOf(int64_t id, int64_t count, int ranks) {
  int64_t base = count / ranks, extra = count % ranks;
  int64_t bigBlocksEnd = extra * (base + 1);
  if (id < bigBlocksEnd) return static_cast<int>(id / (base + 1));
  return static_cast<int>(extra + (id - bigBlocksEnd) / base);
}

Blocks::Blocks(std::vector<int64_t> boundaries) : bound_(std::move(boundaries)) {
  if (bound_.size() < 2 || bound_.front() != 0 || !std::is_sorted(bound_.begin(), bound_.end()))
    throw std::invalid_argument("Blocks: boundaries must start at 0 and not decrease");
}

Blocks Blocks::byCount(int64_t count, int ranks) {
  std::vector<int64_t> bound(ranks + 1);
  for (int r = 0; r < ranks; ++r) bound[r] = blockOf(count, r, ranks).begin;
  bound[ranks] = count;
  return Blocks(std::move(bound));
}

Blocks Blocks::byCost(const std::vector<double>& cost, int ranks) {
  std::vector<int64_t> runStart(cost.size() + 1);
  for (size_t i = 0; i < runStart.size(); ++i) runStart[i] = static_cast<int64_t>(i);
  return byCost(runStart, cost, ranks);
}

Blocks Blocks::byCost(const std::vector<int64_t>& runStart, const std::vector<double>& perPatch,
                      int ranks) {
  const size_t runs = perPatch.size();
  if (runStart.size() != runs + 1 || runStart.front() != 0)
    throw std::invalid_argument("Blocks::byCost: a start per run and the end");
  const int64_t count = runStart.back();
  // Prefix sums in long double: 10^7 terms summed in double would drift by more than the
  // smallest costs.
  std::vector<long double> prefix(runs + 1, 0.0L);
  for (size_t s = 0; s < runs; ++s) {
    const double each = perPatch[s] > 0 ? perPatch[s] : 0.0;  // NaN and negatives: free
    prefix[s + 1] = prefix[s] + static_cast<long double>(each) * (runStart[s + 1] - runStart[s]);
  }
  const long double total = prefix[runs];
  if (!(total > 0) || !std::isfinite(static_cast<double>(total))) return byCount(count, ranks);
  std::vector<int64_t> bound(ranks + 1, 0);
  bound[ranks] = count;
  for (int r = 1; r < ranks; ++r) {
    const long double target = total * r / ranks;
    // The run whose prefix first reaches the target (its cost is > 0), then the patch boundary
    // within it nearest to the target.
    const auto s = static_cast<size_t>(std::lower_bound(prefix.begin() + 1, prefix.end(), target) -
                                       (prefix.begin() + 1));
    int64_t cut = count;
    if (s < runs) {
      const long double within = (target - prefix[s]) / perPatch[s];
      cut = runStart[s] + std::llround(static_cast<double>(within));
      cut = std::clamp(cut, runStart[s], runStart[s + 1]);
    }
    bound[r] = std::max(bound[r - 1], cut);
  }
  return Blocks(std::move(bound));
}

int Blocks::owner(int64_t id) const {
  // The last block starting at or before id that is not empty.
  return static_cast<int>(std::upper_bound(bound_.begin(), bound_.end() - 1, id) - bound_.begin()) -
         1;
}

}  // namespace radiosity::partition
