#include "io/store/result_labels.h"

#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result_format.h"

namespace radiosity {

namespace {

namespace format = result_format;

struct DatasetLabel {
  const char* name;
  const char* units;
  const char* description;
};

// E is in whatever unit the scene gives it (W/m², lux, …): B and H are in that unit too.
constexpr const char* kLight = "the unit of /patches/emission (exitance, e.g. W/m^2)";
// Lengths in the scene's unit: named where the scene states it (length_unit), else said so.
constexpr const char* kLength = "length";
constexpr const char* kArea = "area";

constexpr DatasetLabel kLabels[] = {
    {format::kVertices, kLength, "vertex positions x, y, z"},
    {format::kTriangles, "index",
     "the three vertices of each patch (0-based rows of /mesh/vertices), "
     "counter-clockwise seen from the lit side"},
    {format::kArea, kArea, "patch area"},
    {format::kNormal, "1", "unit normal of the lit side"},
    {format::kReflectance, "1", "diffuse reflectance rho per channel (red, green, blue)"},
    {format::kEmission, "the scene's unit of exitance (e.g. W/m^2)",
     "emitted exitance E per channel"},
    {format::kRadiosity, kLight, "radiosity B per channel: the exitance leaving the patch"},
    {format::kIrradiance, kLight, "irradiance H = sum_j F_ij B_j per channel"},
    {format::kRadiosityStderr, kLight,
     "estimated standard error of B from the sampling of the form factors"},
    {format::kRadiosityDiscretisation, kLight,
     "estimated discretisation error of B (estimated true B minus B)"},
    {format::kHidden, "1",
     "1 where the patch sees nothing (under an object resting on it, inside a solid): left out "
     "of the solve, B = E and H = 0 there"},
    {format::kSourceFace, "index", "0-based index of the input face the patch came from"},
    {format::kRank, "rank", "the MPI rank that owned the patch"},
    {format::kGroup, "index",
     "the patch's group (the scene's label): a row of /groups/view_factors"},
    {format::kDisplayVertices, kLength,
     "vertices of the display mesh: one per distinct position and smooth B (creases split)"},
    {format::kDisplayTriangles, "index", "the patches in order, on /display/vertices"},
    {format::kDisplayRadiosity, kLight,
     "B at the display vertices: area-weighted mean over the patches around the vertex within "
     "30 degrees of each other, of the same reflectance and emission, not hidden (smooth "
     "shading)"},
    {format::kDisplayTonemapped, "1",
     "the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of /display/radiosity tone-mapped to "
     "[0, 1) for a viewer's colour map: Y / (Y + midpoint), midpoint (attribute) the "
     "area-weighted geometric mean of Y over the patches that reflect and do not emit; 0.5 at "
     "a typical wall, near 1 at the lights (Y = midpoint t / (1 - t))"},
    {format::kHistory, "channel, iteration, 1, s",
     "per iteration: channel (0 red, 1 green, 2 blue), iteration, relative residual, seconds"},
    {format::kRowSumHistogram, "patches", "patches per bin of the row sums of F"},
    {format::kRowSumBinEdges, "1", "lower edges of the bins of row_sum_histogram"},
    {format::kRowStart, "index", "F in CSR form: row i is column[row_start[i]:row_start[i+1]]"},
    {format::kColumn, "index", "F in CSR form: the patch j of each F_ij"},
    {format::kValue, "1", "F in CSR form: the form factor F_ij"},
    {format::kGroupArea, kArea,
     "area of each group of patches (the scene's labels: attribute names "
     "of /groups/view_factors)"},
    {format::kViewFactors, "1",
     "view factor F(a -> b) from group a (row) to group b (column): sum over a's patches of "
     "A_i F_ij over b's, over a's area; each the mean of the estimates from a's rays and, by "
     "reciprocity, b's, weighted for the least variance"},
    {format::kViewFactorError, "1",
     "estimated standard error of view_factors: a binomial model of each row's share of the "
     "group, scaled by how far the two estimates of each pair differ (closed-form rows: half "
     "their difference)"},
    {format::kTemperature, "K",
     "temperature of each patch: as given where the thermal file gives it, else from "
     "sigma T^4 = H + q / emissivity"},
    {format::kNetHeatFlux, "W/m^2",
     "net radiative heat flux leaving the patch, J - H (positive where the surface loses heat)"},
    {format::kGroupHeatRate, "W",
     "net radiative heat rate leaving each group (the sum of net_heat_flux times area; "
     "positive where the group loses heat)"},
    {format::kGroupHeatRateError, "W",
     "estimated error of heat_rate: the discretisation and sampling errors of J carried into "
     "the net flux of the group's patches of known temperature"},
};

}  // namespace

void labelResultDatasets(h5::CollectiveSteps& steps, hid_t file, const std::string& lengthUnit,
                         bool thermal) {
  const bool known = !lengthUnit.empty();
  const std::string length = known ? lengthUnit : "the scene's length unit (not stated)";
  const std::string area = known ? lengthUnit + "^2" : "the scene's length unit squared";
  for (const DatasetLabel& label : kLabels) {
    // A thermal run's light is in SI: W/m^2 (its scene in metres).
    const bool light = label.units == kLight || label.name == std::string(format::kEmission);
    const std::string units = label.units == kLength ? length
                              : label.units == kArea ? area
                              : thermal && light     ? "W/m^2"
                                                     : label.units;
    steps.run([&] { labelDataset(file, label.name, units, label.description); });
  }
}

void labelDataset(hid_t file, const char* name, const std::string& units,
                  const std::string& description) {
  if (!h5::exists(file, name)) return;
  h5::Handle dataset =
      h5::own(H5Dopen2(file, name, H5P_DEFAULT), std::string("H5Dopen2(") + name + ")");
  h5::writeStringAttribute(dataset.get(), format_names::attribute::kUnits, units);
  h5::writeStringAttribute(dataset.get(), format_names::attribute::kDescription, description);
}

}  // namespace radiosity
