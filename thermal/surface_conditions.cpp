// Which table of a boundary-condition file each surface of the scene takes, the materials that
// follow from it, and a patch's temperature and flux after the solve.
#include <cmath>
#include <set>
#include <string>

#include "core/error.h"
#include "core/shown_text.h"
#include "core/unicode_spelling.h"
#include "thermal/thermal.h"

namespace radiosity::thermal {

namespace {

// The names a label answers to: itself, its material and its group or object.
std::vector<std::string> namesOf(const std::string& label) {
  std::vector<std::string> names{label};
  for (const char* kind : {" (group ", " (object "}) {
    const size_t at = label.rfind(kind);
    if (at == std::string::npos || label.back() != ')') continue;
    const size_t start = at + std::string(kind).size();
    names.push_back(label.substr(0, at));
    names.push_back(label.substr(start, label.size() - 1 - start));
    break;
  }
  return names;
}

// The table's name where it is one surface's material and another's group or object (not the
// whole label of either): it would apply to both without a word, though a material and a group
// are seldom meant as one. Empty where the name is one or the other throughout.
std::string mixedRoles(const std::string& name, const std::vector<std::string>& surfaces) {
  std::string byMaterial, byGroup;
  for (const std::string& label : surfaces) {
    const std::vector<std::string> names = namesOf(label);
    if (names.size() < 3 || name == label) continue;  // no group, or the whole label
    const bool material = names[1] == name, group = names[2] == name;
    if (material && !group && byMaterial.empty()) byMaterial = label;
    if (group && !material && byGroup.empty()) byGroup = label;
  }
  for (const std::string& label : surfaces)  // a label without a group is its material
    if (namesOf(label).size() == 1 && label == name && byMaterial.empty()) byMaterial = label;
  if (byMaterial.empty() || byGroup.empty()) return "";
  const std::string material = shownText(byMaterial, 80), group = shownText(byGroup, 80);
  std::string text = "'";
  text.append(material).append("' by its material and '").append(group);
  text.append("' by its group or object: give each a table by its whole label ([surface.\"");
  text.append(material).append("\"], [surface.\"").append(group);
  return text.append("\"]), or rename the material or the group");
}

std::string tableName(const SurfaceCondition& c) {
  return c.name.empty() ? "[default]" : "[surface.\"" + shownText(c.name, 80) + "\"]";
}

std::string listOfNames(const std::vector<std::string>& names) {
  std::string list;
  for (size_t k = 0; k < names.size() && k < 12; ++k)
    list += (k == 0 ? "'" : ", '") + shownText(names[k], 60) + "'";
  if (names.size() > 12) list += ", ...";
  return list;
}

}  // namespace

std::vector<int> matchSurfaces(const Mesh& scene, const BoundaryConditions& conditions) {
  const std::string& path = conditions.path;
  std::vector<char> used(scene.labelNames.size(), 0);
  if (scene.hasLabels())
    for (int32_t l : scene.label) used[l] = 1;
  std::vector<std::string> surfaces;  // the labels the triangles use, and what they answer to
  std::set<std::string> answers;
  for (size_t l = 0; l < used.size(); ++l) {
    if (!used[l]) continue;
    surfaces.push_back(scene.labelNames[l]);
    for (const std::string& name : namesOf(scene.labelNames[l])) answers.insert(name);
  }
  for (const SurfaceCondition& c : conditions.surfaces) {
    const std::string mixed = mixedRoles(c.name, surfaces);
    if (!mixed.empty())
      throw InputError(path, c.line, tableName(c) + " names two surfaces in two ways, " + mixed);
    if (answers.count(c.name)) continue;
    if (surfaces.empty())
      throw InputError(
          path, c.line,
          tableName(c) + ": the scene names no materials or groups (" +
              (scene.triangleCount() > 0 ? "its faces carry no names" : "it is empty") +
              "): give its conditions in [default]");
    const std::string spelling =
        spellingDifference(c.name, std::vector<std::string>(answers.begin(), answers.end()));
    throw InputError(path, c.line,
                     tableName(c) + " names no material or group of the scene; " +
                         (spelling.empty() ? "its surfaces: " + listOfNames(surfaces) : spelling));
  }
  std::vector<int> ofLabel(scene.labelNames.size(), -1);
  bool anyTemperature = false;
  auto take = [&](const SurfaceCondition& c) { anyTemperature |= c.knowsTemperature(); };
  if (!scene.hasLabels() && scene.triangleCount() > 0) {
    if (!conditions.fallback)
      throw InputError(path +
                       ": the scene's faces carry no material or group names, so only a "
                       "[default] table can give their condition, and there is none");
    take(*conditions.fallback);
  }
  for (size_t l = 0; l < used.size(); ++l) {
    if (!used[l]) continue;
    int found = -1;
    for (const std::string& name : namesOf(scene.labelNames[l])) {
      for (size_t t = 0; t < conditions.surfaces.size(); ++t) {
        if (conditions.surfaces[t].name != name || found == static_cast<int>(t)) continue;
        if (found >= 0) {
          const SurfaceCondition &a = conditions.surfaces[found], &b = conditions.surfaces[t];
          throw InputError(path, b.line,
                           "the scene's surface '" + shownText(scene.labelNames[l], 80) +
                               "' is named by both " + tableName(a) + " (line " +
                               std::to_string(a.line) + ") and " + tableName(b) +
                               ": give it one condition");
        }
        found = static_cast<int>(t);
      }
    }
    if (found < 0 && !conditions.fallback)
      throw InputError(path + ": the scene's surface '" + shownText(scene.labelNames[l], 80) +
                       "' has no condition: add [surface.\"" +
                       shownText(namesOf(scene.labelNames[l]).back(), 80) +
                       "\"] or a [default] table");
    ofLabel[l] = found;
    take(found >= 0 ? conditions.surfaces[found] : *conditions.fallback);
  }
  if (!anyTemperature && scene.triangleCount() > 0)
    throw InputError(path +
                     ": every surface has a heat_flux and none a temperature: the "
                     "temperatures of a closed enclosure are then fixed only up to a "
                     "constant (a singular system); give at least one surface a "
                     "temperature");
  return ofLabel;
}

void resolveEmissivities(const Mesh& scene, BoundaryConditions& conditions,
                         std::vector<int>& ofLabel) {
  if (!scene.hasLabels()) {
    if (conditions.fallback && !conditions.fallback->emissivityGiven)
      throw InputError(conditions.path, conditions.fallback->line,
                       "[default]: no emissivity (0 < emissivity <= 1), and the scene states "
                       "none");
    return;
  }
  std::vector<char> used(scene.labelNames.size(), 0);
  for (int32_t l : scene.label) used[l] = 1;
  for (size_t l = 0; l < used.size(); ++l) {
    if (!used[l]) continue;
    const SurfaceCondition c = conditionOf(conditions, ofLabel, static_cast<int32_t>(l));
    if (c.emissivityGiven) continue;
    const double stated =
        l < scene.labelEmissivity.size() ? scene.labelEmissivity[l] : std::nan("");
    if (!(stated > 0 && stated <= 1))
      throw InputError(conditions.path, c.line,
                       tableName(c) +
                           ": no emissivity (0 < emissivity <= 1), and the scene "
                           "states none for its surface '" +
                           shownText(scene.labelNames[l], 80) + "'");
    const std::string problem = emissivityProblem(stated);
    if (!problem.empty())
      throw InputError(conditions.path, c.line,
                       tableName(c) + ": no emissivity, and the scene's for its surface '" +
                           shownText(scene.labelNames[l], 80) + "': " + problem +
                           "; give the table one");
    SurfaceCondition own = c;
    own.name = scene.labelNames[l];
    own.emissivity = stated;
    own.emissivityGiven = true;
    conditions.surfaces.push_back(own);
    ofLabel[l] = static_cast<int>(conditions.surfaces.size()) - 1;
  }
}

double BoundaryConditions::surroundingsEmission() const {
  return kStefanBoltzmann * std::pow(surroundingsTemperature, 4);
}

const SurfaceCondition& conditionOf(const BoundaryConditions& conditions,
                                    const std::vector<int>& ofLabel, int32_t label) {
  const int index = label >= 0 && static_cast<size_t>(label) < ofLabel.size() ? ofLabel[label] : -1;
  return index >= 0 ? conditions.surfaces[index] : *conditions.fallback;
}

void applyConditions(Mesh& scene, const BoundaryConditions& conditions,
                     const std::vector<int>& ofLabel) {
  for (int64_t t = 0; t < scene.triangleCount(); ++t) {
    const SurfaceCondition& c =
        conditionOf(conditions, ofLabel, scene.hasLabels() ? scene.label[t] : -1);
    double rho = 1, emission = 0;
    if (c.knowsTemperature()) {
      rho = 1 - c.emissivity;
      emission = c.emissivity * kStefanBoltzmann * std::pow(*c.temperature, 4);
    } else {
      emission = *c.heatFlux;
    }
    scene.reflectance[t] = Rgb{rho, rho, rho};
    scene.emission[t] = Rgb{emission, emission, emission};
  }
}

PatchHeat patchHeat(const SurfaceCondition& c, double radiosity, double irradiance) {
  PatchHeat heat;
  heat.netHeatFlux = radiosity - irradiance;
  if (c.knowsTemperature()) {
    heat.temperature = *c.temperature;
  } else {
    const double emitted = irradiance + heat.netHeatFlux / c.emissivity;  // σT⁴
    heat.temperature = emitted >= 0 ? std::pow(emitted / kStefanBoltzmann, 0.25) : std::nan("");
  }
  return heat;
}

PatchHeatError patchHeatError(const SurfaceCondition& c, const PatchHeat& heat,
                              double irradianceStderr, double irradianceDiscretisation) {
  PatchHeatError error;
  if (c.knowsTemperature()) {
    // q = ε(σT⁴ − H) with T given: q moves by −ε δH.
    error.netHeatFlux = -c.emissivity * irradianceDiscretisation;
    error.netHeatFluxStderr = c.emissivity * irradianceStderr;
  } else if (heat.temperature > 0) {
    // σT⁴ = H + q/ε with q given: σT⁴ moves by δH.
    error.temperature = std::hypot(irradianceStderr, irradianceDiscretisation) /
                        (4 * kStefanBoltzmann * std::pow(heat.temperature, 3));
  }
  return error;
}

}  // namespace radiosity::thermal
