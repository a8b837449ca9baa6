#include "run/solve_json.h"

#include <variant>

#include "core/channels.h"
#include "core/error.h"
#include "io/store/json_text.h"
#include "run/request_options.h"

namespace radiosity::run {

namespace {

using json = JsonDocument;

std::array<double, 3> figures(const ResultAttributes& a, const std::string& prefix) {
  std::array<double, 3> value{};
  for (int c = 0; c < 3; ++c) {
    auto found = a.solveFigures.find(prefix + kChannelNames[c]);
    if (found != a.solveFigures.end()) value[c] = found->second;
  }
  return value;
}

double figure(const ResultAttributes& a, const std::string& key) {
  auto found = a.solveFigures.find(key);
  return found == a.solveFigures.end() ? 0.0 : found->second;
}

json heatJson(const HeatSummary& heat) {
  json surfaces = json::array();
  for (const SurfaceHeat& s : heat.surfaces)
    surfaces.push_back({{"name", s.name},
                        {"given", s.temperatureGiven ? "temperature" : "heat_flux"},
                        {"area_m2", s.area},
                        {"heat_rate_w", s.heatRate},
                        {"heat_rate_error_w", s.heatRateError},
                        {"temperature_k", s.temperature},
                        {"temperature_error_k", s.temperatureError}});
  return {{"surfaces", surfaces},
          {"balance_w", heat.balance},
          {"balance_share", heat.balanceShare},
          {"surroundings_k", heat.surroundingsTemperature}};
}

}  // namespace

std::string solveJson(const SolveSummary& summary) {
  const ResultAttributes& a = *summary.attributes;
  json document = {
      {"schema", "radiosity.solve/1"},
      {"exit_code", exit_code::kOk},
      {"output", summary.output.empty() ? json(nullptr) : json(summary.output)},
  };
  // The options the result records (scene, rays_per_patch, seed, solver, length_unit, thermal),
  // from the table that declares them (run/request_options.h).
  for (const auto& [key, value] : recordedOptions(a))
    document[key] = std::visit([](const auto& v) { return json(v); }, value);
  document.update({
      {"patches", summary.patches},
      {"channels", a.channels},
      {"ranks", a.ranks},
      {"iterations", a.iterations},
      {"residual", a.residual},
      {"converged", a.converged},
      {"left_out", a.leftOut},
      {"refinement_rounds", static_cast<int64_t>(figure(a, "refinement_rounds"))},
  });
  document["estimated_error"] = {
      {"headline", figure(a, "error_estimate")},
      {"B", perChannelJson(a.channels, figures(a, "error_estimate_B_"))},
      {"B_sampling", perChannelJson(a.channels, figures(a, "sampling_error_B_"))},
      {"B_discretisation", perChannelJson(a.channels, figures(a, "discretisation_error_B_"))},
      {"H", perChannelJson(a.channels, figures(a, "error_estimate_H_"))},
  };
  document["stage_seconds"] = a.stageSeconds;
  document["peak_memory_mb"] = summary.peakMegabytes;
  document["solve_figures"] = a.solveFigures;
  if (summary.heat != nullptr) document["heat"] = heatJson(*summary.heat);
  return jsonText(document);
}

}  // namespace radiosity::run
