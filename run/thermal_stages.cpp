// A thermal run's stages of `radiosity solve` (run/solve_pipeline.h): the boundary conditions
// made into the scene's ρ and E after loading, and each patch's temperature and net flux, the
// surfaces' heat rates and the enclosure's balance before writing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "core/shown_text.h"
#include "parallel/collective.h"
#include "run/solve_pipeline.h"

namespace radiosity::run {

namespace {

// The length units a thermal run converts to metres (its fluxes are W/m^2, its rates W).
const std::map<std::string, double>& metresPer() {
  static const std::map<std::string, double> units = {{"m", 1},      {"cm", 1e-2}, {"mm", 1e-3},
                                                      {"um", 1e-6},  {"km", 1e3},  {"in", 0.0254},
                                                      {"ft", 0.3048}};
  return units;
}

const std::string kMetre = "m";

// Sizes in metres past which a scene whose unit is not stated is more likely millimetres (as
// CAD exports are) than metres: hot (furnaces, kilns, ovens) beyond kHotSize, any beyond kAnySize.
constexpr double kHotTemperature = 500, kHotSize = 20, kAnySize = 1000;

// A warning where the scene, its coordinates taken as metres, is larger than its temperatures
// make plausible (a 1,000 mm oven at 1,000 K read as 1,000 m gives gigawatts); "" otherwise.
std::string implausibleSize(const Mesh& scene, const thermal::BoundaryConditions& conditions) {
  if (scene.triangleCount() == 0) return "";
  Vec3 lo, hi;
  scene.boundingBox(lo, hi);
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  double hottest = 0;
  for (const thermal::SurfaceCondition& c : conditions.surfaces)
    hottest = std::max(hottest, c.temperature.value_or(0));
  if (conditions.fallback)
    hottest = std::max(hottest, conditions.fallback->temperature.value_or(0));
  if (size <= kAnySize && (size <= kHotSize || hottest < kHotTemperature)) return "";
  char text[500];
  std::snprintf(text, sizeof text,
                "thermal: the scene states no length unit, and taken as metres it is %.4g m "
                "across with surfaces at up to %.4g K, so that its heat rates are of the order "
                "of %.2g W (sigma T^4 over its area); if its coordinates are not metres, give "
                "--length-unit (mm for a CAD model in millimetres; --length-unit m says they "
                "are metres)",
                size, hottest,
                thermal::kStefanBoltzmann * std::pow(hottest, 4) * scene.totalArea());
  return text;
}

}  // namespace

// Per surface table or group: its heat rate and the parts of its error, in W, and its area and
// area-weighted temperature, summed over the patches and then over the ranks (as doubles).
struct SolvePipeline::HeatSums {
  static constexpr int kCount = 6;
  double rate = 0, discretisation = 0, samplingSquared = 0, area = 0, temperature = 0,
         temperatureError = 0;
  void add(double patchArea, const thermal::PatchHeat& heat, const thermal::PatchHeatError& e) {
    rate += heat.netHeatFlux * patchArea;
    // The discretisation errors are signed and add up (on the closed box the sum matches the
    // error measured against exact view factors); the sampling errors of the patches are
    // taken as independent (summed, coherently, they overstate the error of the concentric
    // spheres' rates seventy-fold: docs/thermal.md).
    discretisation += e.netHeatFlux * patchArea;
    samplingSquared += std::pow(e.netHeatFluxStderr * patchArea, 2);
    area += patchArea;
    temperature += heat.temperature * patchArea;
    temperatureError += e.temperature * patchArea;
  }
  double rateError() const { return std::hypot(discretisation, std::sqrt(samplingSquared)); }
};

// After loading: every surface's condition, the scene's ρ and E from them, and the unit.
void SolvePipeline::applyThermalConditions() {
  runCollectively(console_.comm(), [&] {
    thermal_.conditions = thermal::readBoundaryConditions(request_.thermal);
    thermal_.conditionOfLabel = thermal::matchSurfaces(scene_, thermal_.conditions);
    thermal::resolveEmissivities(scene_, thermal_.conditions, thermal_.conditionOfLabel);
    if (mesh_.lengthUnit.empty()) {
      mesh_.lengthUnit = kMetre;
      const std::string implausible = implausibleSize(scene_, thermal_.conditions);
      if (implausible.empty())
        console_.info(
            "thermal: the scene states no length unit: its coordinates are taken as "
            "metres (--length-unit says otherwise)");
      else
        console_.warn(implausible);
    }
    const auto unit = metresPer().find(mesh_.lengthUnit);
    if (unit == metresPer().end())
      throw Error(exit_code::kUsage, "--thermal: the scene's length unit '" + mesh_.lengthUnit +
                                         "' is not one a thermal run converts to metres (m, cm, "
                                         "mm, um, km, in, ft)");
    thermal_.metresPerUnit = unit->second;
    thermal::applyConditions(scene_, thermal_.conditions, thermal_.conditionOfLabel);
  });
  int known = 0;
  for (const thermal::SurfaceCondition& c : thermal_.conditions.surfaces)
    known += c.knowsTemperature();
  char text[300];
  std::snprintf(text, sizeof text,
                "thermal: %s: %zu surface tables (%d of known temperature)%s; grey diffuse "
                "radiation, one channel, W/m^2",
                request_.thermal.c_str(), thermal_.conditions.surfaces.size(), known,
                thermal_.conditions.fallback ? " and [default]" : "");
  console_.info(text);
  attributes_.channels = 1;
}

// A thermal run's estimator, unless one is named: hemisphere rays, whatever share of the area
// emits. The balance (enforceThermalBalance) brings each column to its row's sum; a closed scene's
// rates sum to 0 only where that sum is 1, which every hemisphere row's is to round-off and an
// emitter-sampled row's only on average (measured in docs/thermal.md).
formfactor::EstimatorChoice SolvePipeline::thermalEstimator() {
  return {formfactor::Estimator::kHemisphere,
          "a thermal run: its rows of a closed scene then sum to 1, and the balance of F makes "
          "the heat rates sum to 0 (emitter sampling's rows sum to 1 only on average)"};
}

// A thermal run's sampled rows are balanced before the solve (solve::balanceColumns: columns
// scaled to what reciprocity says they carry, F's pattern kept), so that the heat rates of a
// closed enclosure sum to 0 to round-off. Exact rows balance to their closed forms' accuracy
// already (~1e-9 of the rates). --reciprocity, if asked for, does it its own way instead.
void SolvePipeline::enforceThermalBalance() {
  formFactors_.balanceColumns = !request_.thermal.empty() && !plan_.reciprocity && !plan_.exactRows;
  if (formFactors_.balanceColumns && plan_.estimator == formfactor::Estimator::kEmitterMis &&
      !thermal_.misBalanceWarned) {
    thermal_.misBalanceWarned = true;
    console_.warn(
        "thermal: --estimator mis: its rows sum to 1 only on average, so the heat rates of a "
        "closed scene sum to 0 only to their sampling noise; --estimator hemisphere (a thermal "
        "run's default) balances them to round-off");
  }
}

// The emission the solve takes: E_i + ρ_i (1 − r_i) σT_amb⁴ with r_i = Σ_j F_ij, the light from
// black surroundings at T_amb that the share of a patch's view leaving the scene brings in and
// the patch reflects (B = E + ρH, H = F B + (1 − r) σT_amb⁴). The scene's own E where the
// surroundings are at 0 K (as before they could be set), or in a lighting run.
std::vector<Rgb> SolvePipeline::emissionWithSurroundings() {
  thermal_.surroundingsIrradiance.clear();
  const double outside = thermal_.conditions.surroundingsEmission();
  if (request_.thermal.empty() || !(outside > 0)) return mesh_.local.emission;
  thermal_.surroundingsIrradiance.assign(mesh_.owned.size(), 0.0);
  std::vector<Rgb> emission = mesh_.local.emission;
  for (size_t r = 0; r < emission.size(); ++r) {
    // A hidden patch sees nothing (ρ = 0 there); a row's sum above 1 by round-off sees none.
    if (mesh_.hidden[mesh_.owned.begin + static_cast<int64_t>(r)]) continue;
    thermal_.surroundingsIrradiance[r] = std::max(0.0, 1 - formFactors_.rowSums[r]) * outside;
    for (int c = 0; c < 3; ++c)
      emission[r][c] += mesh_.local.reflectance[r][c] * thermal_.surroundingsIrradiance[r];
  }
  return emission;
}

// H = F B + (1 − r) σT_amb⁴: the solve's F B with what the surroundings send in.
void SolvePipeline::addSurroundingsIrradiance(std::vector<Rgb>& irradiance) const {
  if (thermal_.surroundingsIrradiance.empty()) return;
  for (size_t r = 0; r < irradiance.size() && r < thermal_.surroundingsIrradiance.size(); ++r)
    for (double& h : irradiance[r]) h += thermal_.surroundingsIrradiance[r];
}

// Before writing: T and q per patch, the heat rate of each surface table and each group with
// its estimated error, and the enclosure's balance Σ q A (0 in a closed enclosure; the net flow
// through its openings to the surroundings otherwise).
void SolvePipeline::recordHeat() {
  const size_t rows = solved_.solution.radiosity.size();
  solved_.solution.temperature.assign(rows, 0);
  solved_.solution.netHeatFlux.assign(rows, 0);
  const double toSquareMetres = thermal_.metresPerUnit * thermal_.metresPerUnit;
  const size_t tables = thermal_.conditions.surfaces.size() + 1;  // the last: [default]
  std::vector<HeatSums> surface(tables), group(formFactors_.groups.names.size());
  double balance[2] = {0, 0};  // Σ q A, Σ |q A|
  int64_t unphysical = 0;
  for (size_t r = 0; r < rows; ++r) {
    const int64_t i = mesh_.owned.begin + static_cast<int64_t>(r);
    const int32_t label = mesh_.patches.hasLabels() ? mesh_.patches.label[i] : -1;
    const int index = label >= 0 ? thermal_.conditionOfLabel[label] : -1;
    const thermal::SurfaceCondition& c =
        thermal::conditionOf(thermal_.conditions, thermal_.conditionOfLabel, label);
    // A hidden patch (under an object resting on it) exchanges nothing.
    thermal::PatchHeat heat{c.temperature.value_or(0), 0};
    if (!mesh_.hidden[i])
      heat = thermal::patchHeat(c, solved_.solution.radiosity[r][0],
                                solved_.solution.irradiance[r][0]);
    if (std::isnan(heat.temperature)) {
      ++unphysical;
      heat.temperature = 0;
    }
    solved_.solution.temperature[r] = heat.temperature;
    solved_.solution.netHeatFlux[r] = heat.netHeatFlux;
    const double area = mesh_.patches.area(i) * toSquareMetres;
    const thermal::PatchHeatError error = thermal::patchHeatError(
        c, heat,
        solved_.solution.irradianceStderr.empty() ? 0.0 : solved_.solution.irradianceStderr[r][0],
        solved_.solution.irradianceDiscretisation.empty()
            ? 0.0
            : solved_.solution.irradianceDiscretisation[r][0]);
    for (HeatSums* sums :
         {&surface[index >= 0 ? index : tables - 1],
          label >= 0 && static_cast<size_t>(label) < group.size() ? &group[label] : nullptr}) {
      if (sums != nullptr) sums->add(area, heat, error);
    }
    balance[0] += heat.netHeatFlux * area;
    balance[1] += std::abs(heat.netHeatFlux * area);
  }
  for (std::vector<HeatSums>* sums : {&surface, &group})
    MPI_Allreduce(MPI_IN_PLACE, sums->data(), static_cast<int>(sums->size() * HeatSums::kCount),
                  MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(MPI_IN_PLACE, balance, 2, MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(MPI_IN_PLACE, &unphysical, 1, MPI_INT64_T, MPI_SUM, comm_);
  if (unphysical > 0)
    throw Error(exit_code::kNumerical,
                request_.thermal + ": " + std::to_string(unphysical) +
                    " patches of known heat_flux would need to absorb more than reaches them "
                    "(sigma T^4 = H + q / emissivity < 0): no temperature satisfies the "
                    "conditions; check the signs of heat_flux (positive: the surface loses heat)");
  formFactors_.groups.heatRate.clear();
  formFactors_.groups.heatRateError.clear();
  for (const HeatSums& g : group) {
    formFactors_.groups.heatRate.push_back(g.rate);
    formFactors_.groups.heatRateError.push_back(g.rateError());
  }
  reportHeat(surface, balance[0], balance[1]);
}

// Each surface table's heat rate and error (or, where its flux is given, its mean temperature
// and error), and the balance: kept for the lines after the write and for --json.
void SolvePipeline::reportHeat(const std::vector<HeatSums>& surface, double balance, double scale) {
  thermal_.heat = HeatSummary{};
  for (size_t t = 0; t < surface.size(); ++t) {
    if (t + 1 == surface.size() && !thermal_.conditions.fallback) break;
    const thermal::SurfaceCondition& c =
        t + 1 < surface.size() ? thermal_.conditions.surfaces[t] : *thermal_.conditions.fallback;
    const HeatSums& s = surface[t];
    // A table no surface takes: [default] where every surface is named, or one without an
    // emissivity, whose surfaces each took a copy with the scene's own (resolveEmissivities).
    if (!(s.area > 0)) continue;
    SurfaceHeat h;
    h.name = c.name.empty() ? "[default]" : c.name;
    h.temperatureGiven = c.knowsTemperature();
    h.area = s.area;
    h.heatRate = s.rate;
    h.heatRateError = h.temperatureGiven ? s.rateError() : 0.0;
    h.temperature = h.temperatureGiven ? *c.temperature : s.temperature / s.area;
    h.temperatureError = h.temperatureGiven ? 0.0 : s.temperatureError / s.area;
    thermal_.heat.surfaces.push_back(h);
  }
  thermal_.heat.balance = balance;
  thermal_.heat.balanceShare = scale > 0 ? balance / scale : 0.0;
  thermal_.heat.surroundingsTemperature = thermal_.conditions.surroundingsTemperature;
  attributes_.solveFigures["thermal_balance_watts"] = balance;
  if (thermal_.conditions.surroundingsTemperature > 0)
    attributes_.solveFigures["thermal_surroundings_kelvin"] =
        thermal_.conditions.surroundingsTemperature;
}

// The heat rates and the balance, what a thermal run is for: on stdout, with -q too (with
// --json, in its document and the log).
void SolvePipeline::printHeat() const {
  std::string line =
      "thermal: net heat rate leaving each surface (W, with its estimated "
      "error) or, where the flux is given, its mean temperature (K):";
  char text[300];
  for (const SurfaceHeat& h : thermal_.heat.surfaces) {
    std::string name = h.name;
    if (name != "[default]") name = std::string("'").append(shownText(name, 80)).append("'");
    if (h.temperatureGiven) {
      std::snprintf(text, sizeof text, "\n  %s: %.6g W +- %.2g", name.c_str(), h.heatRate,
                    h.heatRateError);
    } else {
      std::snprintf(text, sizeof text, "\n  %s: %.6g W (given), mean temperature %.6g K +- %.2g",
                    name.c_str(), h.heatRate, h.temperature, h.temperatureError);
    }
    line += text;
  }
  console_.result(line);
  std::snprintf(text, sizeof text,
                "thermal: balance, the sum of the rates: %.4g W, %.2g of the rates' sizes (0 in "
                "a closed enclosure; otherwise the net flow to the surroundings at %.6g K, "
                "through its openings and the backs of one-sided faces)",
                thermal_.heat.balance, thermal_.heat.balanceShare,
                thermal_.conditions.surroundingsTemperature);
  console_.result(text);
}

}  // namespace radiosity::run
