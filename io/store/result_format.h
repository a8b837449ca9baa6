// The names of the result file (docs/result-format.md, which says what each holds), written once
// for all who name them: the writer (hdf5_result_writer, display_writer), the reader, the
// datasets' labels (result_labels), the XDMF sidecar and the messages that point at a dataset.
//
//   /mesh          vertices [nv,3], triangles [np,3]
//   /patches       one row per patch: area, normal, reflectance, emission, radiosity,
//                  irradiance, radiosity_stderr, radiosity_discretisation, hidden, source_face,
//                  rank, group
//   /display       the smooth-shaded display mesh: vertices [nd,3], triangles [np,3],
//                  radiosity [nd,3], luminance_tonemapped [nd] (attribute `midpoint`)
//   /solve         history [n,4]
//   /formfactors   row_sum_histogram, row_sum_bin_edges; F in CSR form: row_start, column, value
//   /groups        area [G], view_factors [G,G] (attribute `names`), view_factor_error [G,G]
//   root attributes: see `attribute` below; time_<stage>, solve_<figure>, software_<name>
#pragma once

#include "io/store/format_names.h"

namespace radiosity::result_format {

/// The newest format_version this program writes and reads.
inline constexpr int kFormatVersion = 1;

// The groups and their datasets, a declaration per group.
using format_names::kMesh, format_names::kVertices, format_names::kTriangles;
inline constexpr char kPatches[] = "/patches", kArea[] = "/patches/area",
                      kNormal[] = "/patches/normal", kReflectance[] = "/patches/reflectance",
                      kEmission[] = "/patches/emission", kRadiosity[] = "/patches/radiosity",
                      kIrradiance[] = "/patches/irradiance",
                      kRadiosityStderr[] = "/patches/radiosity_stderr",
                      kRadiosityDiscretisation[] = "/patches/radiosity_discretisation",
                      kHidden[] = "/patches/hidden", kSourceFace[] = "/patches/source_face",
                      kRank[] = "/patches/rank", kGroup[] = "/patches/group",
                      kTemperature[] = "/patches/temperature",
                      kNetHeatFlux[] = "/patches/net_heat_flux";
inline constexpr char kDisplay[] = "/display", kDisplayVertices[] = "/display/vertices",
                      kDisplayTriangles[] = "/display/triangles",
                      kDisplayRadiosity[] = "/display/radiosity",
                      kDisplayTonemapped[] = "/display/luminance_tonemapped";
using format_names::kFormFactors, format_names::kRowStart, format_names::kColumn;
using format_names::kSolve, format_names::kHistory;
inline constexpr char kRowSumHistogram[] = "/formfactors/row_sum_histogram",
                      kRowSumBinEdges[] = "/formfactors/row_sum_bin_edges",
                      kValue[] = "/formfactors/value";
inline constexpr char kGroups[] = "/groups", kGroupArea[] = "/groups/area",
                      kViewFactors[] = "/groups/view_factors",
                      kViewFactorError[] = "/groups/view_factor_error",
                      kGroupHeatRate[] = "/groups/heat_rate",
                      kGroupHeatRateError[] = "/groups/heat_rate_error";

/// The XDMF sidecar's name for /display/radiosity (its cell data take their /patches names, and
/// /display/luminance_tonemapped its own).
inline constexpr char kSmoothRadiosity[] = "radiosity_smooth";

/// Attribute names: of the root, and `names` of /groups/view_factors.
namespace attribute {
using namespace format_names::attribute;
inline constexpr char kRanks[] = "ranks", kRaysPerPatch[] = "rays_per_patch", kSeed[] = "seed",
                      kSolver[] = "solver", kLeftOut[] = "left_out", kIterations[] = "iterations",
                      kResidual[] = "residual", kConverged[] = "converged", kScene[] = "scene",
                      kOptions[] = "options", kSolverChoice[] = "solver_choice",
                      kThermal[] = "thermal";
/// Families of root attributes: time_<stage> (wall seconds), solve_<figure>.
inline constexpr char kStageTimePrefix[] = "time_", kSolveFigurePrefix[] = "solve_";
inline constexpr char kGroupNames[] = "names";  ///< of /groups/view_factors: the labels
/// Of /display/luminance_tonemapped: the luminance it shows as 0.5.
inline constexpr char kMidpoint[] = "midpoint";
}  // namespace attribute

}  // namespace radiosity::result_format
