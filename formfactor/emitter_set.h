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
    Vec3 normal;  ///< the patch's, as Mesh::normal gives it
  };
  /// u1 picks the patch (by area), (u2, u3) the point on it: uniform over the total area.
  Sample sample(double u1, double u2, double u3) const;
  /// The same, uniform over the area of one light.
  Sample sampleLight(int64_t light, double u1, double u2, double u3) const;

 private:
  /// Emitting patches by light, each light's in id order; lights numbered by their first patch.
  std::vector<int64_t> patch_;
  /// The corners and the normal of each, in patch_'s order: a draw lands on a random emitter of
  /// the whole scene, and reads one record instead of the mesh's triangle, three vertices and
  /// their normal, each a cache miss of its own (in a thermal scene, where most surfaces emit,
  /// those misses were most of the discretisation estimate's shadow rays' time).
  struct Corners {
    Vec3 v0, v1, v2, normal;
  };
  std::vector<Corners> corners_;
  std::vector<double> cumulativeArea_;  ///< running sums over patch_, last = totalArea_
  /// Chen and Asau's guide table: guide_[k] is where the running sums pass k/n of the total
  /// (n = guide_.size() - 1), so that a draw searches a bracket of about one patch instead of
  /// all of them (a binary search over 10^5 emitters of a thermal scene was half the direct
  /// light's time); the patch found is the same.
  std::vector<int64_t> guide_;
  /// The first index whose running sum exceeds `target` (std::upper_bound over them all).
  size_t firstAbove(double target) const;
  /// The point at (u2, u3) on emitter `index` (of patch_'s order).
  Sample at(size_t index, double u2, double u3) const;
  std::vector<int64_t> lightStart_;  ///< light l holds patch_[lightStart_[l], lightStart_[l+1])
  std::vector<double> lightArea_;
  /// Emitting patch ids in ascending order and the light of each, for lightOf().
  std::vector<int64_t> sortedPatch_;
  std::vector<int64_t> lightOfSorted_;
  double totalArea_ = 0;
};

}  // namespace radiosity::formfactor
