// Private to formfactor/: which light the emitter sample of a row aims at. Uniform over the
// emitters' area wastes the samples of a large scene: in a building of 5,000 rooms a patch sees
// its own room's lamp and a few through doors, and 4,999 of 5,000 area samples land behind
// walls. So rows are taken in clusters of kClusterPatches consecutive patches (neighbours along
// the space-filling curve), and a pilot of each cluster (its own samples, independent of the
// rows') estimates how much light each lamp sends it; the rows' emitter samples then pick a lamp
// in proportion to that, mixed with the old uniform choice for lamps the pilot missed: a share
// of at least kByArea, more when the pilot says much light comes from lamps it saw once
// (Good–Turing's estimate of the unseen share: lamps seen once over all the samples that saw a
// lamp), as among thousands of small lamps, where weights from a few hundred samples would
// starve the lamps they missed. Any choice keeps MIS unbiased, as long as the density it is
// weighted with is the one it samples: the balance heuristic's weights of the two samples add up to
// 1 wherever either density is positive, and the hemisphere density is positive everywhere above
// the patch.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "formfactor/emitter_set.h"

namespace radiosity::formfactor {

/// Patches per cluster sharing one pilot, and the pilot's samples (a hemisphere and an area
/// sample each, as in a row). Measured on builtin:rooms (docs/design/form-factors.md, "Light
/// choice").
inline constexpr int64_t kClusterPatches = 64;
inline constexpr int64_t kLightPilotSamples = 256;
/// The least share of emitter samples still drawn uniform over all emitters' area.
inline constexpr double kByArea = 0.1;

class LightChoice {
 public:
  /// Uniform over all emitters' area (one light, or a pilot that found none).
  explicit LightChoice(const EmitterSet& emitters) : emitters_(&emitters) {}
  /// `byArea` (at least kByArea) uniform over the area, the rest over the lights in proportion
  /// to `weights` (light, weight > 0), sorted by light.
  LightChoice(const EmitterSet& emitters, const std::vector<std::pair<int64_t, double>>& weights,
              double byArea);

  /// A point on an emitter: u1 picks the light and the patch on it, (u2, u3) the point.
  EmitterSet::Sample sample(double u1, double u2, double u3) const;
  /// The density of sample()'s points per unit area on emitting patch j.
  double densityPerArea(int64_t j) const;

 private:
  const EmitterSet* emitters_;
  std::vector<int64_t> light_;      ///< the lights the pilot saw, ascending
  double byArea_ = 1;               ///< the share drawn uniform over the area
  std::vector<double> share_;       ///< of the emitter samples, per light_ (sum 1 - byArea_)
  std::vector<double> cumulative_;  ///< running sums of share_
};

}  // namespace radiosity::formfactor
