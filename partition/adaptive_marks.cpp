// Which patches an adaptive refinement round splits: bulk marking (Dörfler) on the estimated
// error each patch's variation puts into the light the others gather.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "partition/partition.h"

namespace radiosity::partition {

namespace {

// Classes of patches whose errors lie within a factor 2^(1/8) of each other. The marks are
// taken a class at a time, so that an error that differs by round-off between runs on other
// numbers of ranks (it is computed from B) changes the marks only if it crosses a class edge.
constexpr double kClassesPerOctave = 8;

int64_t errorClass(int64_t error) {
  return static_cast<int64_t>(
      std::floor(std::log2(static_cast<double>(error)) * kClassesPerOctave));
}

}  // namespace

std::vector<int64_t> markLargestErrors(const std::vector<int64_t>& error, double share,
                                       int64_t maxMarks, int64_t minMarks) {
  std::vector<int64_t> order;
  long double total = 0;
  for (size_t t = 0; t < error.size(); ++t) {
    if (error[t] <= 0) continue;
    order.push_back(static_cast<int64_t>(t));
    total += static_cast<long double>(error[t]);
  }
  std::vector<int64_t> klass(error.size(), 0);
  for (int64_t t : order) klass[t] = errorClass(error[t]);
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return klass[a] > klass[b]; });
  std::vector<int64_t> marked;
  long double taken = 0;
  for (size_t first = 0;
       first < order.size() && (taken < share * total || static_cast<int64_t>(first) < minMarks);) {
    size_t end = first;
    while (end < order.size() && klass[order[end]] == klass[order[first]]) {
      taken += static_cast<long double>(error[order[end]]);
      ++end;
    }
    marked.insert(marked.end(), order.begin() + first, order.begin() + end);
    first = end;
  }
  if (static_cast<int64_t>(marked.size()) > maxMarks) marked.resize(std::max<int64_t>(0, maxMarks));
  return marked;
}

std::vector<int64_t> markFlatBisections(const std::vector<Bisection>& candidates,
                                        const std::vector<int64_t>& error,
                                        const std::vector<char>& mergeable, double errorBudget) {
  struct Star {
    int64_t vertex, error, klass;
  };
  std::vector<Star> stars;
  for (const Bisection& b : candidates) {
    int64_t sum = 0;
    bool ok = true;
    for (int64_t t : b.halves) {
      if (t < 0) continue;
      ok = ok && mergeable[t];
      sum += std::max<int64_t>(0, error[t]);
    }
    // A star without error (black, hidden) comes first, in a class of its own.
    if (ok) stars.push_back({b.vertex, sum, sum > 0 ? errorClass(sum) : INT64_MIN});
  }
  std::stable_sort(stars.begin(), stars.end(),
                   [](const Star& a, const Star& b) { return a.klass < b.klass; });
  std::vector<int64_t> taken;
  long double spent = 0;
  for (size_t first = 0; first < stars.size();) {
    size_t end = first;
    long double classError = 0;
    while (end < stars.size() && stars[end].klass == stars[first].klass)
      classError += static_cast<long double>(stars[end++].error);
    if (spent + classError > errorBudget) break;
    spent += classError;
    for (size_t s = first; s < end; ++s) taken.push_back(stars[s].vertex);
    first = end;
  }
  std::sort(taken.begin(), taken.end());
  return taken;
}

}  // namespace radiosity::partition
