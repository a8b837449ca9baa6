// Which estimator serves a scene: decided from the share of the area that emits.
#include <cstdio>

#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

EstimatorChoice chooseEstimator(const Mesh& patches) {
  double emitting = 0, total = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const double area = patches.area(t);
    const Rgb& e = patches.emission[t];
    total += area;
    if (e[0] > 0 || e[1] > 0 || e[2] > 0) emitting += area;
  }
  const double share = total > 0 ? emitting / total : 0.0;
  char reason[200];
  if (emitting == 0) {
    return {Estimator::kHemisphere, "nothing emits: no emitter to sample"};
  }
  if (share < kMisEmitterShare) {
    std::snprintf(reason, sizeof reason,
                  "emitters are %.3g %% of the area: their light is sampled directly as well as "
                  "found by hemisphere rays (2 rays per sample, far less noise in direct light)",
                  100 * share);
    return {Estimator::kEmitterMis, reason};
  }
  std::snprintf(reason, sizeof reason,
                "emitters are %.3g %% of the area: hemisphere rays find them as well as emitter "
                "sampling would, at 1 ray per sample instead of 2",
                100 * share);
  return {Estimator::kHemisphere, reason};
}

}  // namespace radiosity::formfactor
