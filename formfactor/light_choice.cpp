#include "formfactor/light_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

LightChoice::LightChoice(const EmitterSet& emitters,
                         const std::vector<std::pair<int64_t, double>>& weights, double byArea)
    : emitters_(&emitters) {
  double total = 0;
  for (const auto& [light, weight] : weights) total += weight;
  byArea = std::max(byArea, kByArea);
  if (!(total > 0) || byArea >= 1) return;
  byArea_ = byArea;
  double running = 0;
  for (const auto& [light, weight] : weights) {
    light_.push_back(light);
    share_.push_back((1 - byArea_) * weight / total);
    running += share_.back();
    cumulative_.push_back(running);
  }
}

EmitterSet::Sample LightChoice::sample(double u1, double u2, double u3) const {
  if (light_.empty()) return emitters_->sample(u1, u2, u3);
  if (u1 < byArea_) return emitters_->sample(u1 / byArea_, u2, u3);
  // The rest of u1 picks the light, and what is left of it within the light's share the patch:
  // the sequence's even spread in u1 carries over to both (a smaller error than with the light
  // picked by a dimension of its own).
  const double v = u1 - byArea_;
  const auto found = std::upper_bound(cumulative_.begin(), cumulative_.end(), v);
  const size_t k = std::min<size_t>(found - cumulative_.begin(), light_.size() - 1);
  const double before = k == 0 ? 0.0 : cumulative_[k - 1];
  const double within = std::clamp((v - before) / share_[k], 0.0, std::nextafter(1.0, 0.0));
  return emitters_->sampleLight(light_[k], within, u2, u3);
}

double LightChoice::densityPerArea(int64_t j) const {
  const double byArea = 1 / emitters_->totalArea();
  if (light_.empty()) return byArea;
  const int64_t light = emitters_->lightOf(j);
  const auto found = std::lower_bound(light_.begin(), light_.end(), light);
  const double chosen = found != light_.end() && *found == light
                            ? share_[found - light_.begin()] / emitters_->lightArea(light)
                            : 0.0;
  return byArea_ * byArea + chosen;
}

std::string misLightChoice() {
  char words[120];
  std::snprintf(
      words, sizeof words,
      "per %lld patches by a pilot of %lld samples, by area at least %g or lamps seen once",
      static_cast<long long>(kClusterPatches), static_cast<long long>(kLightPilotSamples), kByArea);
  return words;
}

}  // namespace radiosity::formfactor
