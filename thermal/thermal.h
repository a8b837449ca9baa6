// thermal: grey diffuse radiation exchange in SI units on the radiosity system. A thermal
// boundary-condition file (TOML) gives every surface of the scene an emissivity ε and either a
// temperature T or a net radiative heat flux q. Both kinds are rows of (I − diag(ρ) F) J = E:
// a known temperature emits εσT⁴ and reflects 1 − ε; a known flux is the row J − Σ_j F_ij J_j = q,
// i.e. ρ = 1 and E = q. After the solve, J and H = F J give each patch its flux and temperature.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::thermal {

/// The Stefan-Boltzmann constant, W m^-2 K^-4 (CODATA 2018, exact in SI since 2019).
inline constexpr double kStefanBoltzmann = 5.670374419e-8;

/// The least emissivity a boundary condition takes. A known temperature is the row
/// J − (1 − ε) H = εσT⁴: as ε goes to 0 it tends to J = H, which holds for any T, and the
/// system to the singular one of fluxes alone (ρ = 1 everywhere). Below this its condition
/// number (about 1/ε) leaves the heat rates no digits (docs/thermal.md).
inline constexpr double kLeastEmissivity = 1e-6;

/// Why `emissivity` is no boundary condition's (above 1, below kLeastEmissivity, NaN), or "".
std::string emissivityProblem(double emissivity);

/// One table of the file: [surface."NAME"] or [default].
struct SurfaceCondition {
  std::string name;  ///< the material or group name; empty for [default]
  long line = 0;     ///< of the table's header, for messages
  double emissivity = 1;
  std::optional<double> temperature;  ///< K
  std::optional<double> heatFlux;     ///< W/m², the net flux leaving the surface
  /// false: the table gives none, and each of its surfaces takes the one the scene states
  /// (Mesh::labelEmissivity; resolveEmissivities).
  bool emissivityGiven = true;
  bool knowsTemperature() const { return temperature.has_value(); }
};

struct BoundaryConditions {
  std::string path;                          ///< the file, for messages
  std::vector<SurfaceCondition> surfaces;    ///< in the file's order
  std::optional<SurfaceCondition> fallback;  ///< [default]
  /// [surroundings] temperature, K: black surroundings that every share of a patch's view
  /// reaching no surface (1 − Σ_j F_ij: openings, backs of one-sided faces) sees. 0 by default.
  double surroundingsTemperature = 0;
  long surroundingsLine = 0;  ///< of its `temperature`; 0 where the file gives none
  /// σT⁴ of the surroundings, W/m²: what they send into a patch per unit of its unseen view.
  double surroundingsEmission() const;
};

/// Reads and checks a boundary-condition file: only [surface."NAME"] tables, a [default]
/// table and a [surroundings] table (temperature, K, finite and ≥ 0); in each, `emissivity` in (0,
/// 1] (or none: the scene's, resolveEmissivities) and exactly one of `temperature` (K, ≥ 0) and
/// `heat_flux` (W/m²), finite, with εσT⁴ and |q| within the emission the solver takes; no other
/// key. Throws InputError naming the file and line (exit 3).
BoundaryConditions readBoundaryConditions(const std::string& path);
/// The same from text (`path` names it in messages).
BoundaryConditions parseBoundaryConditions(const std::string& text, const std::string& path);

/// Per label of `scene` (Mesh::labelNames), the index in conditions.surfaces of the table that
/// names its material or its group (or object), or -1 for [default]. A label is 'material',
/// 'material (group G)' or 'material (object O)'; the whole label matches too. Throws InputError
/// when a table names no surface of the scene, when a surface matches two tables, when a surface
/// has no condition and there is no [default], and when no surface has a temperature (the
/// temperatures of a closed enclosure would then be fixed only up to a constant).
std::vector<int> matchSurfaces(const Mesh& scene, const BoundaryConditions& conditions);

/// Gives the surfaces whose table has no `emissivity` the one the scene states for them: each
/// such surface gets a table of its own (a copy named after it, appended to conditions.surfaces
/// and set in ofLabel). Throws InputError (the table's line) where the scene states none.
void resolveEmissivities(const Mesh& scene, BoundaryConditions& conditions,
                         std::vector<int>& ofLabel);

/// Sets every triangle's ρ and E (all channels alike) from its condition: ρ = 1 − ε and
/// E = εσT⁴ for a known temperature, ρ = 1 and E = q for a known flux. `ofLabel`: matchSurfaces.
void applyConditions(Mesh& scene, const BoundaryConditions& conditions,
                     const std::vector<int>& ofLabel);

/// A patch's temperature and net flux from its condition and the solve's J and H (W/m²).
struct PatchHeat {
  double temperature = 0;  ///< K; NaN where a known flux asks for more than arrives
  double netHeatFlux = 0;  ///< W/m², positive where the surface loses heat
};
/// q = J − H: with a reciprocal F whose rows sum to 1, Σ q_i A_i of a closed enclosure is 0
/// to round-off whatever J is. Known temperature: that T; known flux: T from σT⁴ = H + q/ε.
PatchHeat patchHeat(const SurfaceCondition& condition, double radiosity, double irradiance);

/// The estimated errors of a patch's flux and temperature, from H's estimated sampling error
/// (standard error) and discretisation error (signed, true minus computed), which the solve
/// gives on every patch, black ones (ε = 1, ρ = 0) too. Known temperature: q = ε(σT⁴ − H), so
/// q moves by −ε δH. Known flux: σT⁴ = H + q/ε moves by δH.
struct PatchHeatError {
  double netHeatFlux = 0;        ///< signed, from the discretisation error
  double netHeatFluxStderr = 0;  ///< from the sampling error
  double temperature = 0;        ///< both together, K
};
PatchHeatError patchHeatError(const SurfaceCondition& condition, const PatchHeat& heat,
                              double irradianceStderr, double irradianceDiscretisation);

/// The condition of each label, [default] where ofLabel is -1.
const SurfaceCondition& conditionOf(const BoundaryConditions& conditions,
                                    const std::vector<int>& ofLabel, int32_t label);

}  // namespace radiosity::thermal
