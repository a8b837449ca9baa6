// The form-factor estimators and their names, parsed once on the command line.
#pragma once

#include <stdexcept>
#include <string>

#include "core/enum_names.h"

namespace radiosity::formfactor {

/// How the rows are estimated.
enum class Estimator {
  /// Cosine-weighted hemisphere sampling: 1 ray per sample; closed scenes' rows sum to 1.
  kHemisphere,
  /// Hemisphere sampling combined with area sampling of the emitting patches by multiple
  /// importance sampling (balance heuristic): 2 rays per sample, far less noise in direct light.
  kEmitterMis,
};

/// The estimators' names on the command line, in the logs and in the result file, with what
/// --help says of each.
inline constexpr NamedValue<Estimator> kEstimatorNames[] = {
    {Estimator::kHemisphere, "hemisphere", "1 ray per sample"},
    {Estimator::kEmitterMis, "mis",
     "hemisphere and emitter sampling by multiple importance sampling, 2 rays per sample"},
};

/// Rays cast per sample: what a row of N samples can hold at most is N times this.
inline int raysPerSample(Estimator estimator) {
  return estimator == Estimator::kEmitterMis ? 2 : 1;
}

/// The estimator's name: "hemisphere" or "mis".
inline const char* estimatorName(Estimator estimator) { return nameIn(kEstimatorNames, estimator); }

/// The estimator of that name; throws std::invalid_argument for any other.
inline Estimator estimatorNamed(const std::string& name) {
  if (const auto estimator = valueNamed(kEstimatorNames, name)) return *estimator;
  throw std::invalid_argument("unknown estimator '" + name + "'");
}

}  // namespace radiosity::formfactor
