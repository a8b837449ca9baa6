// formfactor: the rows F_i· of the form-factor matrix by Monte Carlo ray casting, and the ray
// tracer (Embree, kept behind this header) that render/ reuses for camera rays.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "io/io.h"

namespace radiosity::formfactor {

/// An Embree BVH over every triangle of a mesh; the triangle index is the patch id.
/// Thread-safe for queries once built. Owns its Embree device and scene.
class SceneTracer {
 public:
  explicit SceneTracer(const Mesh& mesh);
  ~SceneTracer();
  SceneTracer(const SceneTracer&) = delete;
  SceneTracer& operator=(const SceneTracer&) = delete;

  struct Hit {
    int64_t patch;
    double distance;
    double u, v;  ///< barycentric coordinates of the hit: p = (1-u-v)·v0 + u·v1 + v·v2
  };
  /// The first triangle hit along origin + t·direction for t in (tNear, tFar), any side.
  std::optional<Hit> intersect(Vec3 origin, Vec3 direction, double tNear,
                               double tFar = 1e300) const;

  /// Length of the bounding box diagonal: the yardstick for ray offsets.
  double sceneSize() const { return sceneSize_; }

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;  ///< owned
  double sceneSize_ = 0;
};

struct Options {
  int64_t raysPerPatch = 1024;
  uint64_t seed = 1;
};

/// Sparse rows in CSR form: row r (global patch id firstRow + r) holds columns
/// column[rowStart[r] .. rowStart[r+1]) sorted ascending, with values F_ij > 0.
struct SparseRows {
  int64_t firstRow = 0;
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<double> value;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
  int64_t nonzeros() const { return static_cast<int64_t>(column.size()); }
};

/// Counts gathered while sampling (this rank's rows only).
struct Statistics {
  int64_t raysCast = 0;
  int64_t backFaceHits = 0;  ///< absorbed: many of them mean wrong winding
  /// backFaceHits split by the label of the patch whose back was hit (Mesh::labelNames order);
  /// empty if the mesh has no labels.
  std::vector<int64_t> backFaceHitsByLabel;
  int64_t escapedRays = 0;  ///< left the scene (open scenes)
  double minRowSum = 0, maxRowSum = 0, sumRowSums = 0;
};

/// Called now and then with the number of this rank's rows finished so far.
using ProgressCallback = std::function<void(int64_t rowsDone)>;

/// Estimates F_ij for the patches [firstPatch, endPatch) by cosine-weighted hemisphere sampling
/// from stratified points: F_ij ≈ (rays from i whose first hit is the front of j) / N. Every
/// random number is keyed by (seed, global patch id, sample index), so a row is the same
/// whichever rank computes it.
SparseRows computeRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress = {});

}  // namespace radiosity::formfactor
