// The emitting patches as one light for area sampling: a point uniform over their total area.
#pragma once

#include <cstdint>
#include <vector>

#include "io/core/mesh.h"

namespace radiosity::formfactor {

class EmitterSet {
 public:
  /// Every patch with E > 0 in some channel.
  explicit EmitterSet(const Mesh& patches);

  bool empty() const { return patch_.empty(); }
  double totalArea() const { return totalArea_; }

  struct Sample {
    int64_t patch;
    Vec3 point;
  };
  /// u1 picks the patch (by area), (u2, u3) the point on it: uniform over the total area.
  Sample sample(const Mesh& patches, double u1, double u2, double u3) const;

 private:
  std::vector<int64_t> patch_;
  std::vector<double> cumulativeArea_;  ///< running sums, last = totalArea_
  double totalArea_ = 0;
};

}  // namespace radiosity::formfactor
