// The emitting patches, for area sampling, grouped into lights: a light is a connected piece of
// emitting patches (corners at the same position join them), such as one lamp's tessellation.
// Points are drawn uniform over a light's area; which light, LightChoice decides.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace radiosity::formfactor {

class EmitterSet {
 public:
  /// Every patch with E > 0 in some channel, grouped into lights.
  explicit EmitterSet(const Mesh& patches);

  bool empty() const { return patch_.empty(); }
  double totalArea() const { return totalArea_; }
  int64_t lightCount() const { return static_cast<int64_t>(lightArea_.size()); }
  double lightArea(int64_t light) const { return lightArea_[light]; }
  /// The light emitting patch j belongs to (j must emit).
  int64_t lightOf(int64_t j) const;

  struct Sample {
    int64_t patch;
    Vec3 point;
  };
  /// u1 picks the patch (by area), (u2, u3) the point on it: uniform over the total area.
  Sample sample(const Mesh& patches, double u1, double u2, double u3) const;
  /// The same, uniform over the area of one light.
  Sample sampleLight(const Mesh& patches, int64_t light, double u1, double u2, double u3) const;

 private:
  /// Emitting patches by light, each light's in id order; lights numbered by their first patch.
  std::vector<int64_t> patch_;
  std::vector<double> cumulativeArea_;  ///< running sums over patch_, last = totalArea_
  std::vector<int64_t> lightStart_;     ///< light l holds patch_[lightStart_[l], lightStart_[l+1])
  std::vector<double> lightArea_;
  /// Emitting patch ids in ascending order and the light of each, for lightOf().
  std::vector<int64_t> sortedPatch_;
  std::vector<int64_t> lightOfSorted_;
  double totalArea_ = 0;
};

}  // namespace radiosity::formfactor
