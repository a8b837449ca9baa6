// What the run decides for itself as it goes: the settings a request leaves to it ("auto") and
// those a round changes (--target-error's rays). The request (run/solve_request.h) never
// changes; the pipeline keeps one plan, and a round that may not happen is tried on a copy.
#pragma once

#include <cstdint>
#include <optional>

#include "formfactor/estimator.h"
#include "run/solve_request.h"

namespace radiosity::run {

struct RunPlan {
  int64_t rays = 1024;  ///< rays per patch of this round (--rays, then --target-error's)
  /// The estimator: --estimator's, until the scene's is chosen (formfactor::chooseEstimator).
  std::optional<formfactor::Estimator> estimator;
  bool exactRows = false;        ///< rows by closed forms (formfactor::chooseRows), per round
  bool pairsOnce = false;        ///< exact rows stored once a pair (storesPairsOnce), per round
  bool singlePrecision = false;  ///< F's values in single precision (storesSinglePrecision)
  bool reciprocity = false;      ///< --reciprocity, or enforced for a solver that needs it (cg)
};

/// The plan before anything is chosen: what `request` asks for.
inline RunPlan initialPlan(const SolveRequest& request) {
  RunPlan plan;
  plan.rays = request.raysPerPatch;
  plan.estimator = request.estimator;
  plan.reciprocity = request.reciprocity;
  return plan;
}

}  // namespace radiosity::run
