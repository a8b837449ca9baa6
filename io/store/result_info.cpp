// `radiosity info` of an HDF5 file: its datasets and root attributes, and for a result file a
// summary of what it holds (io/store/result.h: describeResult).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/shown_text.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result.h"
#include "io/store/result_format.h"
#include "io/store/result_reading.h"
#include "io/store/result_summary.h"
#include "measure/light_error.h"

namespace radiosity {
namespace {

namespace format = result_format;

using h5::exact;
using h5::exists;
using h5::readString;
using h5::shapeOf;
using h5::shapeText;
using h5::typeName;

/// "name = value" for any root attribute: numbers exactly, text as is (multi-line text indented
/// on the lines below), arrays as [a, b, ...].
std::string attributeText(hid_t file, const std::string& name) {
  const AttributeValue attribute = readAttribute(file, name);
  std::vector<std::string> items;
  switch (attribute.kind) {
    case AttributeValue::Kind::kText: {
      if (attribute.text.find('\n') == std::string::npos)
        return shownText(name) + " = \"" + shownText(attribute.text, 2000) + "\"";
      std::string value;
      std::istringstream lines(attribute.text);
      for (std::string line; std::getline(lines, line);)
        value += "\n      " + shownText(line, 2000);
      return shownText(name) + " =" + value;
    }
    case AttributeValue::Kind::kOther:
      return shownText(name) + " : " + attribute.text;
    case AttributeValue::Kind::kFloat:
      for (double v : attribute.floats) items.push_back(exact(v));
      break;
    case AttributeValue::Kind::kSigned:
      for (long long v : attribute.signeds) items.push_back(std::to_string(v));
      break;
    case AttributeValue::Kind::kUnsigned:
      for (unsigned long long v : attribute.unsigneds) items.push_back(std::to_string(v));
      break;
  }
  if (items.size() == 1) return shownText(name) + " = " + items[0];
  std::string value;
  for (size_t i = 0; i < items.size(); ++i) value += (i ? ", " : "") + items[i];
  return shownText(name) + " = [" + value + "]";
}

/// The root attribute an `options` line restates: --seed 1 is `seed = 1`, --rays 64
/// `rays_per_patch = 64`.
std::string attributeOfOption(std::string key) {
  if (key == "rays") return "rays_per_patch";
  std::replace(key.begin(), key.end(), '-', '_');
  return key;
}

/// The `options` attribute without the lines a root attribute states with the same value (the
/// scene, seed, ranks, rays, thermal file), which info would print twice.
std::string optionsText(hid_t file, const std::string& name) {
  const AttributeValue attribute = readAttribute(file, name);
  if (attribute.kind != AttributeValue::Kind::kText) return attributeText(file, name);
  std::string value;
  std::istringstream lines(attribute.text);
  for (std::string line; std::getline(lines, line);) {
    const size_t equals = line.find(" = ");
    if (equals != std::string::npos) {
      const size_t start = line.find_first_not_of(' ');
      const std::string key = attributeOfOption(line.substr(start, equals - start)),
                        given = line.substr(equals + 3);
      if (key != name && H5Aexists(file, key.c_str()) > 0) {
        const std::string stated = attributeText(file, key);
        if (stated == key + " = " + given || stated == key + " = \"" + given + "\"") continue;
      }
    }
    value += "\n      " + shownText(line, 2000);
  }
  return shownText(name) + " =" + value;
}

std::string fixed(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%14.6g", value);
  return text;
}

/// A row of the summary's table: its label, then R, G and B times `scale`.
void tableRow(std::ostream& out, const char* label, const Rgb& v, double scale) {
  char text[40];
  std::snprintf(text, sizeof text, "  %-28s", label);
  out << text;
  for (int k = 0; k < 3; ++k) out << fixed(v[k] * scale);
  out << "\n";
}

/// The estimated error in the measure of measure/light_error.h: sampling alone, and with the
/// discretisation estimate where the file has one.
void describeEstimatedError(std::ostream& out, const Result& r) {
  const EstimatedErrors errors = estimatedErrors(r);
  tableRow(out, "estimated sampling error", errors.sampling, 1);
  if (errors.total) tableRow(out, "estimated error (with discr.)", *errors.total, 1);
  out << "    (RMS over the reflecting patches of each patch's error relative to its own B)\n";
}

/// The row sums' histogram and the size of F, where the file has them.
void describeFormFactors(std::ostream& out, const Result& r) {
  const size_t np = r.radiosity.size();
  if (!r.rowSumHistogram.empty()) {
    out << "  row sums of F, patches per bin from its lower edge:";
    for (size_t k = 0; k < r.rowSumHistogram.size(); ++k) {
      out << (k == 0 ? " " : " | ")
          << (k < r.rowSumBinEdges.size() ? exact(r.rowSumBinEdges[k]) : std::string("?")) << ": "
          << r.rowSumHistogram[k];
    }
    out << "\n";
  }
  if (r.formFactors)
    out << "  form factors: " << r.formFactors->nonzeros() << " nonzeros ("
        << (np ? double(r.formFactors->nonzeros()) / np : 0.0) << " per row)\n";
}

/// Each channel's last entry in the solve history.
void describeHistory(std::ostream& out, const SolveHistory& history) {
  out << "  solve history: " << history.size() << " entries\n";
  for (int c = 0; c < 3; ++c) {
    // The channel's last entry in the history (channels are validated to be 0 to 2).
    for (size_t i = history.size(); i-- > 0;) {
      if (history.channel[i] != c) continue;
      out << "    " << kChannelNames[c] << ": last iteration " << history.iteration[i]
          << ", residual " << exact(history.residual[i]) << ", at " << exact(history.seconds[i])
          << " s\n";
      break;
    }
  }
}

/// A thermal result's one channel in SI: J, q and T over the patches, each group's heat rate
/// (W) and mean temperature, and the balance; not R, G, B and powers in W/m² × length².
void describeHeat(std::ostream& out, const Result& r) {
  const HeatTotals heat = heatTotals(r);
  out << "  thermal (one channel, SI: W/m^2, W, K):\n";
  char text[400];
  std::snprintf(text, sizeof text,
                "    radiosity J (W/m^2):      min %-12.6g mean %-12.6g max %.6g\n"
                "    net heat flux q (W/m^2):  min %-12.6g max %.6g\n"
                "    temperature (K):          min %-12.6g max %.6g\n",
                heat.lowJ, heat.meanJ, heat.highJ, heat.lowQ, heat.highQ, heat.lowT, heat.highT);
  out << text;
  if (!heat.groups.empty())
    out << "    heat rate leaving each group (W), its estimated error, mean temperature:\n";
  for (const HeatTotals::Group& g : heat.groups) {
    std::snprintf(text, sizeof text, ": %.6g W +- %.2g, %.6g K\n", g.rate, g.error, g.temperature);
    out << "      '" << shownText(g.name, 80) << "'" << text;
  }
  if (!std::isnan(heat.balance)) {
    std::snprintf(text, sizeof text, "    balance, the sum of the rates: %.4g W\n", heat.balance);
    out << text;
  }
}

std::string summaryOf(const Result& r) {
  const size_t np = r.radiosity.size();
  const LightTotals totals = lightTotals(r);
  std::ostringstream out;
  out << "summary:\n"
      << "  patches: " << np << "\n"
      << "  vertices: " << r.mesh.vertices.size() << "\n"
      << "  total area: " << exact(totals.area) << "\n";
  if (!r.hidden.empty()) {
    out << "  hidden patches (see nothing; left out of the solve): "
        << std::count(r.hidden.begin(), r.hidden.end(), 1) << "\n";
  }
  if (!r.attributes.thermal.empty()) {
    describeHeat(out, r);
  } else {
    out << "                                           R             G             B\n";
    tableRow(out, "radiosity min", totals.low, 1);
    tableRow(out, "radiosity mean", totals.sum, np ? 1.0 / np : 0);
    tableRow(out, "radiosity max", totals.high, 1);
    tableRow(out, "emitted power sum(A*E)", totals.emitted, 1);
    tableRow(out, "reflected power sum(A*(B-E))", totals.reflected, 1);
    if (!r.radiosityStderr.empty()) describeEstimatedError(out, r);
  }
  describeFormFactors(out, r);
  // (the solver's choice, the software and the solve figures are root attributes, listed once)
  if (r.attributes.history.size() > 0) describeHistory(out, r.attributes.history);
  return out.str();
}

}  // namespace

std::string describeResult(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = h5::openFile(path, "result file");
  std::ostringstream out;
  out << "file: " << path << "\n";
  try {
    const std::vector<std::string> datasets = datasetNames(file.get());
    out << "datasets:\n";
    for (const std::string& name : datasets) {
      h5::Handle dataset =
          h5::own(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
      h5::Handle type = h5::own(H5Dget_type(dataset.get()), "H5Dget_type(" + name + ")");
      h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space(" + name + ")");
      char line[256];
      std::snprintf(line, sizeof line, "  %-24s %-8s %s\n", shownText(name).c_str(),
                    typeName(type.get()).c_str(), shapeText(shapeOf(space.get())).c_str());
      out << line;
    }
    out << "attributes:\n";
    for (const std::string& name : h5::attributeNames(file.get()))
      out << "  "
          << (name == format::attribute::kOptions ? optionsText(file.get(), name)
                                                  : attributeText(file.get(), name))
          << "\n";
    // A checkpoint or other HDF5 file is listed; a result is also summarised, and must be whole.
    if (exists(file.get(), format::kPatches) || exists(file.get(), format::kMesh))
      out << summaryOf(readOpenResult(file.get(), path));
  } catch (const h5::Failure& e) {
    h5::fail(path, e.what());
  }
  return out.str();
}

}  // namespace radiosity
