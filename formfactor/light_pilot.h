// Private to formfactor/: the pilot that makes a cluster's light choice (light_choice.h). One
// per thread: its ray buffers are reused from cluster to cluster.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "formfactor/emitter_set.h"
#include "formfactor/formfactor.h"
#include "formfactor/light_choice.h"

namespace radiosity::formfactor {

class LightPilot {
 public:
  /// Keeps references to all four, which must outlive it; `normals`: of every patch.
  LightPilot(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
             const EmitterSet& emitters)
      : tracer_(tracer), patches_(patches), normals_(normals), emitters_(emitters) {}

  /// The light choice of the cluster of patches [first, end), from kLightPilotSamples MIS
  /// samples (emitter samples uniform over the area) spread over its patches, keyed by `seed`.
  LightChoice choose(int64_t first, int64_t end, uint64_t seed);

  /// The rays cast since the last call, which starts the count again.
  int64_t takeRaysCast() { return std::exchange(raysCast_, 0); }

 private:
  /// Each hemisphere sample of the pilot that reached an emitter, and each unshadowed emitter
  /// sample: (its light, MIS weight × the mean emission of the patch reached).
  void traceHemisphereSamples(int64_t first, int64_t end, int64_t each, uint64_t seed,
                              std::vector<std::pair<int64_t, double>>& seen);
  void traceEmitterSamples(int64_t each, uint64_t seed,
                           std::vector<std::pair<int64_t, double>>& seen);

  const SceneTracer& tracer_;
  const Mesh& patches_;
  const std::vector<Vec3>& normals_;
  const EmitterSet& emitters_;
  int64_t raysCast_ = 0;
  SceneTracer::RayBatch patchRays_;  ///< one patch's hemisphere rays
  std::vector<uint32_t> scratch_;
  // The pilot's rays, the patch each leaves from, and each emitter sample's target and weight.
  SceneTracer::RayBatch rays_;
  SceneTracer::HitBatch hits_;
  std::vector<int64_t> patch_, target_;
  std::vector<double> weight_;
};

}  // namespace radiosity::formfactor
