// The direct light on the Cornell box's floor by a form-factor estimator, and its error against
// a reference of many more samples: for the test that MIS beats the hemisphere there
// (formfactor_sampling_test.cpp) and for bench/estimator_error.cpp's table.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "formfactor/formfactor.h"
#include "sampled_form_factors.h"

namespace radiosity::testing {

/// The patches of `cornell` on its floor (facing up, below y = 1), the first `most` of them.
inline std::vector<int64_t> cornellFloor(const Mesh& cornell,
                                         size_t most = std::numeric_limits<size_t>::max()) {
  std::vector<int64_t> floor;
  for (int64_t t = 0; t < cornell.triangleCount(); ++t)
    if (cornell.normal(t).y > 0.99 && cornell.centroid(t).y < 1 && floor.size() < most)
      floor.push_back(t);
  return floor;
}

/// Direct irradiance of the floor's patches, H_i = Σ_{j emitting} F_ij E_j (red), from
/// `samples` per patch.
inline std::vector<double> floorDirectIrradiance(const Mesh& cornell,
                                                 const trace::SceneTracer& tracer,
                                                 const std::vector<int64_t>& floor, int64_t samples,
                                                 formfactor::Estimator estimator, uint64_t seed) {
  std::vector<double> irradiance;
  for (int64_t i : floor) {
    formfactor::Statistics s;
    const formfactor::SparseRows row =
        sampledFormFactors(tracer, cornell, i, i + 1, {samples, seed, estimator}, s);
    double h = 0;
    for (int64_t k = 0; k < row.nonzeros(); ++k)
      h += row.value[k] * cornell.emission[row.column[k]][0];
    irradiance.push_back(h);
  }
  return irradiance;
}

/// The RMS of `estimate` − `reference` over the patches, divided by the reference's mean (each
/// patch's relative error would be ruled by the patches in half shadow).
inline double rmsErrorOverMean(const std::vector<double>& estimate,
                               const std::vector<double>& reference) {
  double squares = 0, mean = 0;
  for (size_t p = 0; p < reference.size(); ++p) {
    squares += std::pow(estimate[p] - reference[p], 2);
    mean += reference[p];
  }
  mean /= reference.size();
  return std::sqrt(squares / reference.size()) / mean;
}

}  // namespace radiosity::testing
