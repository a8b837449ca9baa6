#include "io/store/result_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "measure/light_error.h"

namespace radiosity {

AttributeValue readAttribute(hid_t file, const std::string& name) {
  h5::Handle attribute = h5::own(H5Aopen(file, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  h5::Handle type = h5::own(H5Aget_type(attribute.get()), "H5Aget_type(" + name + ")");
  h5::Handle space = h5::own(H5Aget_space(attribute.get()), "H5Aget_space(" + name + ")");
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  const H5T_class_t typeClass = H5Tget_class(type.get());
  AttributeValue value;
  if (typeClass == H5T_STRING && count == 1) {
    value.kind = AttributeValue::Kind::kText;
    value.text = h5::readString(attribute.get(), type.get(), "attribute " + name);
  } else if ((typeClass != H5T_INTEGER && typeClass != H5T_FLOAT) || count < 1) {
    value.text = h5::typeName(type.get()) + " " + h5::shapeText(h5::shapeOf(space.get()));
  } else if (typeClass == H5T_FLOAT) {
    value.kind = AttributeValue::Kind::kFloat;
    value.floats.resize(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, value.floats.data()),
              "H5Aread(" + name + ")");
  } else if (H5Tget_sign(type.get()) == H5T_SGN_NONE) {
    value.kind = AttributeValue::Kind::kUnsigned;
    value.unsigneds.resize(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_ULLONG, value.unsigneds.data()),
              "H5Aread(" + name + ")");
  } else {
    value.kind = AttributeValue::Kind::kSigned;
    value.signeds.resize(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_LLONG, value.signeds.data()),
              "H5Aread(" + name + ")");
  }
  return value;
}

std::vector<std::string> datasetNames(hid_t file) {
  std::vector<std::string> links;
  auto collect = [](hid_t, const char* name, const H5L_info_t* info, void* data) -> herr_t {
    if (info->type == H5L_TYPE_HARD)
      static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
    return 0;
  };
  h5::check(H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, collect, &links), "H5Lvisit");
  std::vector<std::string> datasets;
  for (const std::string& link : links) {
    h5::Handle object = h5::own(H5Oopen(file, link.c_str(), H5P_DEFAULT), "H5Oopen(" + link + ")");
    if (H5Iget_type(object.get()) == H5I_DATASET) datasets.push_back(link);
  }
  return datasets;
}

LightTotals lightTotals(const Result& r) {
  const size_t np = r.radiosity.size();
  LightTotals totals;
  for (int k = 0; k < 3; ++k) {
    totals.low[k] = np ? std::numeric_limits<double>::infinity() : 0;
    totals.high[k] = np ? -std::numeric_limits<double>::infinity() : 0;
  }
  for (size_t i = 0; i < np; ++i) {
    totals.area += r.area[i];
    for (int k = 0; k < 3; ++k) {
      const double b = r.radiosity[i][k], e = r.mesh.emission[i][k];
      totals.low[k] = std::min(totals.low[k], b);
      totals.high[k] = std::max(totals.high[k], b);
      totals.sum[k] += b;
      totals.emitted[k] += r.area[i] * e;
      // B = E + ρH: what leaves a patch beyond its own emission is reflected.
      totals.reflected[k] += r.area[i] * (b - e);
    }
  }
  return totals;
}

HeatTotals heatTotals(const Result& r) {
  HeatTotals totals;
  const size_t np = r.radiosity.size();
  const auto range = [&](const auto& value, double& low, double& high) {
    low = np ? std::numeric_limits<double>::infinity() : 0;
    high = np ? -std::numeric_limits<double>::infinity() : 0;
    for (size_t i = 0; i < np; ++i) {
      low = std::min(low, value(i));
      high = std::max(high, value(i));
    }
  };
  range([&](size_t i) { return r.radiosity[i][0]; }, totals.lowJ, totals.highJ);
  range([&](size_t i) { return r.netHeatFlux.empty() ? 0.0 : r.netHeatFlux[i]; }, totals.lowQ,
        totals.highQ);
  range([&](size_t i) { return r.temperature.empty() ? 0.0 : r.temperature[i]; }, totals.lowT,
        totals.highT);
  for (size_t i = 0; i < np; ++i) totals.meanJ += r.radiosity[i][0] / static_cast<double>(np);
  const GroupFactors& g = r.groups;
  const size_t groups = g.heatRate.size() == g.names.size() ? g.names.size() : 0;
  std::vector<double> sum(groups, 0), area(groups, 0);
  for (size_t i = 0; i < np && !r.temperature.empty(); ++i) {
    const auto l = static_cast<size_t>(r.mesh.hasLabels() ? r.mesh.label[i] : -1);
    if (l >= groups) continue;
    sum[l] += r.area[i] * r.temperature[i];
    area[l] += r.area[i];
  }
  for (size_t l = 0; l < groups; ++l)
    totals.groups.push_back({g.names[l], g.heatRate[l],
                             l < g.heatRateError.size() ? g.heatRateError[l] : 0.0,
                             area[l] > 0 ? sum[l] / area[l] : 0.0});
  const auto balance = r.attributes.solveFigures.find("thermal_balance_watts");
  totals.balance = balance == r.attributes.solveFigures.end() ? std::nan("") : balance->second;
  return totals;
}

EstimatedErrors estimatedErrors(const Result& r) {
  // Hidden patches were left out of the solve (B = E exactly): they count as reflecting nothing
  // in the error figures, as in the solve's own.
  std::vector<Rgb> rho = r.mesh.reflectance;
  for (size_t t = 0; t < r.hidden.size(); ++t)
    if (r.hidden[t]) rho[t] = Rgb{0, 0, 0};
  EstimatedErrors errors;
  errors.sampling = relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, r.radiosityStderr);
  if (!r.radiosityDiscretisation.empty()) {
    const size_t np = r.radiosity.size();
    std::vector<Rgb> total(np);
    for (size_t i = 0; i < np; ++i)
      for (int k = 0; k < 3; ++k)
        total[i][k] = std::hypot(r.radiosityStderr[i][k], r.radiosityDiscretisation[i][k]);
    errors.total = relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, total);
  }
  return errors;
}

}  // namespace radiosity
