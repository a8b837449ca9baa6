// `radiosity info --json`: what describeResult lists, as one JSON document
// (docs/json-summaries.md, schema "radiosity.info/1").
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/channels.h"
#include "io/store/checkpoint_format.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/json_text.h"
#include "io/store/result.h"
#include "io/store/result_format.h"
#include "io/store/result_reading.h"
#include "io/store/result_summary.h"
#include "io/store/scene_file_format.h"

namespace radiosity {
namespace {

using json = JsonDocument;

json attributeJson(const AttributeValue& value) {
  switch (value.kind) {
    case AttributeValue::Kind::kText:
      return value.text;
    case AttributeValue::Kind::kOther:
      return json{{"type", value.text}};
    case AttributeValue::Kind::kFloat:
      return value.floats.size() == 1 ? json(value.floats[0]) : json(value.floats);
    case AttributeValue::Kind::kSigned:
      return value.signeds.size() == 1 ? json(value.signeds[0]) : json(value.signeds);
    case AttributeValue::Kind::kUnsigned:
      return value.unsigneds.size() == 1 ? json(value.unsigneds[0]) : json(value.unsigneds);
  }
  return nullptr;
}

// A thermal result's figures in SI (W/m², W, K): what its R, G, B summary cannot say.
json heatJson(const Result& r) {
  const HeatTotals heat = heatTotals(r);
  json groups = json::array();
  for (const HeatTotals::Group& g : heat.groups)
    groups.push_back({{"name", g.name},
                      {"heat_rate_w", g.rate},
                      {"heat_rate_error_w", g.error},
                      {"mean_temperature_k", g.temperature}});
  return {{"radiosity_w_m2", {{"min", heat.lowJ}, {"mean", heat.meanJ}, {"max", heat.highJ}}},
          {"net_heat_flux_w_m2", {{"min", heat.lowQ}, {"max", heat.highQ}}},
          {"temperature_k", {{"min", heat.lowT}, {"max", heat.highT}}},
          {"groups", groups},
          {"balance_w", std::isnan(heat.balance) ? json(nullptr) : json(heat.balance)}};
}

json summaryJson(const Result& r) {
  const int channels = r.attributes.channels;
  const size_t np = r.radiosity.size();
  const LightTotals totals = lightTotals(r);
  Rgb mean = totals.sum;
  for (double& m : mean) m = np ? m / static_cast<double>(np) : 0;
  json summary = {
      {"patches", np},
      {"vertices", r.mesh.vertices.size()},
      {"total_area", totals.area},
      {"channels", channels},
      {"thermal", !r.attributes.thermal.empty()},
      {"radiosity",
       {{"min", perChannelJson(channels, totals.low)},
        {"mean", perChannelJson(channels, mean)},
        {"max", perChannelJson(channels, totals.high)}}},
      {"emitted_power", perChannelJson(channels, totals.emitted)},
      {"reflected_power", perChannelJson(channels, totals.reflected)},
  };
  summary["length_unit"] =
      r.attributes.lengthUnit.empty() ? json(nullptr) : json(r.attributes.lengthUnit);
  if (!r.hidden.empty())
    summary["hidden_patches"] = std::count(r.hidden.begin(), r.hidden.end(), 1);
  if (!r.radiosityStderr.empty()) {
    const EstimatedErrors errors = estimatedErrors(r);
    summary["estimated_error"] = {{"sampling", perChannelJson(channels, errors.sampling)}};
    if (errors.total) summary["estimated_error"]["total"] = perChannelJson(channels, *errors.total);
  }
  if (!r.attributes.thermal.empty()) summary["heat"] = heatJson(r);
  if (r.formFactors) summary["formfactor_nonzeros"] = r.formFactors->nonzeros();
  summary["solve_history_entries"] = r.attributes.history.size();
  return summary;
}

}  // namespace

std::string describeFileJson(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = h5::openFile(path, "result file");
  json document = {{"schema", "radiosity.info/1"}, {"file", path}};
  try {
    const std::string kind = h5::kindAttribute(file.get());
    document["kind"] = kind.empty() ? json(nullptr) : json(kind);
    json datasets = json::array();
    for (const std::string& name : datasetNames(file.get())) {
      h5::Handle dataset =
          h5::own(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
      h5::Handle type = h5::own(H5Dget_type(dataset.get()), "H5Dget_type(" + name + ")");
      h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space(" + name + ")");
      datasets.push_back({{"name", name},
                          {"type", h5::typeName(type.get())},
                          {"shape", h5::shapeOf(space.get())}});
    }
    document["datasets"] = datasets;
    json attributes = json::object();
    for (const std::string& name : h5::attributeNames(file.get()))
      attributes[name] = attributeJson(readAttribute(file.get(), name));
    document["attributes"] = attributes;
    // A result (a file of ours of no other kind) is also summarised, and must be whole (as
    // describeResult).
    const bool otherKind = kind == checkpoint_format::kKind || kind == scene_format::kKind;
    if (!otherKind && (h5::exists(file.get(), result_format::kPatches) ||
                       h5::exists(file.get(), result_format::kMesh)))
      document["summary"] = summaryJson(readOpenResult(file.get(), path));
  } catch (const h5::Failure& e) {
    h5::fail(path, e.what());
  }
  return jsonText(document);
}

}  // namespace radiosity
