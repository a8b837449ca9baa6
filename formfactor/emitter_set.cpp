#include "formfactor/emitter_set.h"

#include <algorithm>
#include <numeric>
#include <tuple>

#include "trace/sample_warps.h"

namespace radiosity::formfactor {

namespace {

bool emits(const Rgb& e) { return e[0] > 0 || e[1] > 0 || e[2] > 0; }

// The root of k, halving the path on the way (union-find).
int64_t rootOf(std::vector<int64_t>& parent, int64_t k) {
  while (parent[k] != k) k = parent[k] = parent[parent[k]];
  return k;
}

// For each emitting patch (by its index in `emitting`) a label shared exactly by the patches of
// its connected piece: corners at the same position connect, whether or not the mesh welded
// them into one vertex. Labels are the smallest index of the piece.
std::vector<int64_t> connectedPieces(const Mesh& patches, const std::vector<int64_t>& emitting) {
  const auto n = static_cast<int64_t>(emitting.size());
  struct Corner {
    Vec3 position;
    int64_t emitter;
  };
  std::vector<Corner> corners;
  corners.reserve(3 * emitting.size());
  for (int64_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) corners.push_back({patches.corner(emitting[k], c), k});
  }
  auto key = [](const Corner& a) { return std::tie(a.position.x, a.position.y, a.position.z); };
  std::sort(corners.begin(), corners.end(),
            [&](const Corner& a, const Corner& b) { return key(a) < key(b); });
  std::vector<int64_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t k = 1; k < corners.size(); ++k) {
    if (key(corners[k]) != key(corners[k - 1])) continue;
    const int64_t a = rootOf(parent, corners[k].emitter),
                  b = rootOf(parent, corners[k - 1].emitter);
    parent[std::max(a, b)] = std::min(a, b);  // the smaller index stays the root
  }
  std::vector<int64_t> label(n);
  for (int64_t k = 0; k < n; ++k) label[k] = rootOf(parent, k);
  return label;
}

}  // namespace

EmitterSet::EmitterSet(const Mesh& patches) {
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    if (emits(patches.emission[t])) sortedPatch_.push_back(t);
  }
  const std::vector<int64_t> piece = connectedPieces(patches, sortedPatch_);
  // Lights numbered in order of their first patch; patches by light, then by id.
  std::vector<int64_t> order(sortedPatch_.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return piece[a] < piece[b]; });
  lightOfSorted_.assign(sortedPatch_.size(), 0);
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || piece[order[k]] != piece[order[k - 1]]) {
      lightStart_.push_back(static_cast<int64_t>(k));
      lightArea_.push_back(0);
    }
    const int64_t t = sortedPatch_[order[k]];
    patch_.push_back(t);
    corners_.push_back(
        {patches.corner(t, 0), patches.corner(t, 1), patches.corner(t, 2), patches.normal(t)});
    totalArea_ += patches.area(t);
    lightArea_.back() += patches.area(t);
    cumulativeArea_.push_back(totalArea_);
    lightOfSorted_[order[k]] = lightCount() - 1;
  }
  lightStart_.push_back(static_cast<int64_t>(patch_.size()));
  const size_t n = patch_.size();
  guide_.resize(n + 1);
  for (size_t k = 0; k <= n; ++k) {
    const double share = static_cast<double>(k) / static_cast<double>(n) * totalArea_;
    guide_[k] = std::upper_bound(cumulativeArea_.begin(), cumulativeArea_.end(), share) -
                cumulativeArea_.begin();
  }
}

size_t EmitterSet::firstAbove(double target) const {
  const size_t n = patch_.size();
  if (n == 0) return 0;
  const double position = target / totalArea_ * static_cast<double>(n);
  const size_t k = position > 0 ? std::min(n - 1, static_cast<size_t>(position)) : 0;
  // The bracket [guide_[k], guide_[k + 1]] holds the answer but for round-off in `position`:
  // widened while it does not.
  size_t low = guide_[k], high = guide_[k + 1];
  while (low > 0 && cumulativeArea_[low - 1] > target) --low;
  while (high < n && !(cumulativeArea_[high] > target)) ++high;
  return std::upper_bound(cumulativeArea_.begin() + static_cast<std::ptrdiff_t>(low),
                          cumulativeArea_.begin() + static_cast<std::ptrdiff_t>(high), target) -
         cumulativeArea_.begin();
}

int64_t EmitterSet::lightOf(int64_t j) const {
  const auto found = std::lower_bound(sortedPatch_.begin(), sortedPatch_.end(), j);
  return lightOfSorted_[found - sortedPatch_.begin()];
}

EmitterSet::Sample EmitterSet::sample(double u1, double u2, double u3) const {
  return at(std::min<size_t>(firstAbove(u1 * totalArea_), patch_.size() - 1), u2, u3);
}

EmitterSet::Sample EmitterSet::at(size_t index, double u2, double u3) const {
  const Corners& c = corners_[index];
  return {patch_[index], trace::pointOnTriangle(c.v0, c.v1, c.v2, u2, u3), c.normal};
}

EmitterSet::Sample EmitterSet::sampleLight(int64_t light, double u1, double u2, double u3) const {
  const int64_t first = lightStart_[light];
  const double before = first == 0 ? 0.0 : cumulativeArea_[first - 1];
  // (the running sums rise: the first above the target in the light's span is the first above
  // it in them all, which lies at or after the span's start since target >= before)
  const size_t end = lightStart_[light + 1];
  return at(std::min<size_t>(firstAbove(before + u1 * lightArea_[light]), end - 1), u2, u3);
}

}  // namespace radiosity::formfactor
