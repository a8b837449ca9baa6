#include "io/store/result_labels.h"

#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"

namespace radiosity {

namespace {

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
    {"/mesh/vertices", kLength, "vertex positions x, y, z"},
    {"/mesh/triangles", "index",
     "the three vertices of each patch (0-based rows of /mesh/vertices), "
     "counter-clockwise seen from the lit side"},
    {"/patches/area", kArea, "patch area"},
    {"/patches/normal", "1", "unit normal of the lit side"},
    {"/patches/reflectance", "1", "diffuse reflectance rho per channel (red, green, blue)"},
    {"/patches/emission", "the scene's unit of exitance (e.g. W/m^2)",
     "emitted exitance E per channel"},
    {"/patches/radiosity", kLight, "radiosity B per channel: the exitance leaving the patch"},
    {"/patches/irradiance", kLight, "irradiance H = sum_j F_ij B_j per channel"},
    {"/patches/radiosity_stderr", kLight,
     "estimated standard error of B from the sampling of the form factors"},
    {"/patches/radiosity_discretisation", kLight,
     "estimated discretisation error of B (estimated true B minus B)"},
    {"/patches/hidden", "1",
     "1 where the patch sees nothing (under an object resting on it, inside a solid): left out "
     "of the solve, B = E and H = 0 there"},
    {"/patches/source_face", "index", "0-based index of the input face the patch came from"},
    {"/patches/rank", "rank", "the MPI rank that owned the patch"},
    {"/patches/group", "index",
     "the patch's group (the scene's label): a row of /groups/view_factors"},
    {"/display/vertices", kLength,
     "vertices of the display mesh: one per distinct position and smooth B (creases split)"},
    {"/display/triangles", "index", "the patches in order, on /display/vertices"},
    {"/display/radiosity", kLight,
     "B at the display vertices: area-weighted mean over the patches around the vertex within "
     "30 degrees of each other, of the same reflectance and emission, not hidden (smooth "
     "shading)"},
    {"/solve/history", "channel, iteration, 1, s",
     "per iteration: channel (0 red, 1 green, 2 blue), iteration, relative residual, seconds"},
    {"/formfactors/row_sum_histogram", "patches", "patches per bin of the row sums of F"},
    {"/formfactors/row_sum_bin_edges", "1", "lower edges of the bins of row_sum_histogram"},
    {"/formfactors/row_start", "index",
     "F in CSR form: row i is column[row_start[i]:row_start[i+1]]"},
    {"/formfactors/column", "index", "F in CSR form: the patch j of each F_ij"},
    {"/formfactors/value", "1", "F in CSR form: the form factor F_ij"},
    {"/groups/area", kArea,
     "area of each group of patches (the scene's labels: attribute names "
     "of /groups/view_factors)"},
    {"/groups/view_factors", "1",
     "view factor F(a -> b) from group a (row) to group b (column): sum over a's patches of "
     "A_i F_ij over b's, over a's area; each the mean of the estimates from a's rays and, by "
     "reciprocity, b's, weighted for the least variance"},
};

}  // namespace

void labelResultDatasets(h5::CollectiveSteps& steps, hid_t file, const std::string& lengthUnit) {
  const bool known = !lengthUnit.empty();
  const std::string length = known ? lengthUnit : "the scene's length unit (not stated)";
  const std::string area = known ? lengthUnit + "^2" : "the scene's length unit squared";
  for (const DatasetLabel& label : kLabels) {
    steps.run([&] {
      if (!h5::exists(file, label.name)) return;
      h5::Handle dataset = h5::own(H5Dopen2(file, label.name, H5P_DEFAULT),
                                   std::string("H5Dopen2(") + label.name + ")");
      const std::string units = label.units == kLength ? length
                                : label.units == kArea ? area
                                                       : label.units;
      h5::writeStringAttribute(dataset.get(), "units", units);
      h5::writeStringAttribute(dataset.get(), "description", label.description);
    });
  }
}

}  // namespace radiosity
