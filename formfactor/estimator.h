// The form-factor estimators and their names, parsed once on the command line.
#pragma once

#include <stdexcept>
#include <string>

namespace radiosity::formfactor {

/// How the rows are estimated.
enum class Estimator {
  /// Cosine-weighted hemisphere sampling: 1 ray per sample; closed scenes' rows sum to 1.
  kHemisphere,
  /// Hemisphere sampling combined with area sampling of the emitting patches by multiple
  /// importance sampling (balance heuristic): 2 rays per sample, far less noise in direct light.
  kEmitterMis,
};

/// The estimator's name on the command line and in the logs: "hemisphere" or "mis".
inline const char* estimatorName(Estimator estimator) {
  switch (estimator) {
    case Estimator::kHemisphere:
      return "hemisphere";
    case Estimator::kEmitterMis:
      return "mis";
  }
  return "unknown";
}

/// The estimator of that name; throws std::invalid_argument for any other.
inline Estimator estimatorNamed(const std::string& name) {
  for (Estimator estimator : {Estimator::kHemisphere, Estimator::kEmitterMis}) {
    if (name == estimatorName(estimator)) return estimator;
  }
  throw std::invalid_argument("unknown estimator '" + name + "'");
}

}  // namespace radiosity::formfactor
