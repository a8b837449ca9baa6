#include "formfactor/emitter_set.h"

#include <algorithm>

#include "formfactor/sample_warps.h"

namespace radiosity::formfactor {

EmitterSet::EmitterSet(const Mesh& patches) {
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const Rgb& e = patches.emission[t];
    if (e[0] > 0 || e[1] > 0 || e[2] > 0) {
      patch_.push_back(t);
      totalArea_ += patches.area(t);
      cumulativeArea_.push_back(totalArea_);
    }
  }
}

EmitterSet::Sample EmitterSet::sample(const Mesh& patches, double u1, double u2, double u3) const {
  const double target = u1 * totalArea_;
  auto found = std::upper_bound(cumulativeArea_.begin(), cumulativeArea_.end(), target);
  const size_t index = std::min<size_t>(found - cumulativeArea_.begin(), patch_.size() - 1);
  const int64_t t = patch_[index];
  return {
      t, pointOnTriangle(patches.corner(t, 0), patches.corner(t, 1), patches.corner(t, 2), u2, u3)};
}

}  // namespace radiosity::formfactor
