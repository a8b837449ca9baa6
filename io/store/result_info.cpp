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
#include "io/store/light_error.h"
#include "io/store/result.h"
#include "io/store/result_format.h"
#include "io/store/result_reading.h"

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
  h5::Handle attribute = h5::own(H5Aopen(file, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  h5::Handle type = h5::own(H5Aget_type(attribute.get()), "H5Aget_type(" + name + ")");
  h5::Handle space = h5::own(H5Aget_space(attribute.get()), "H5Aget_space(" + name + ")");
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  const H5T_class_t typeClass = H5Tget_class(type.get());
  std::string value;
  if (typeClass == H5T_STRING && count == 1) {
    const std::string text = readString(attribute.get(), type.get(), "attribute " + name);
    if (text.find('\n') == std::string::npos)
      return shownText(name) + " = \"" + shownText(text, 2000) + "\"";
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) value += "\n      " + shownText(line, 2000);
    return shownText(name) + " =" + value;
  }
  if ((typeClass != H5T_INTEGER && typeClass != H5T_FLOAT) || count < 1)
    return shownText(name) + " : " + typeName(type.get()) + " " + shapeText(shapeOf(space.get()));
  std::vector<std::string> items;
  if (typeClass == H5T_FLOAT) {
    std::vector<double> values(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, values.data()), "H5Aread(" + name + ")");
    for (double v : values) items.push_back(exact(v));
  } else if (H5Tget_sign(type.get()) == H5T_SGN_NONE) {
    std::vector<unsigned long long> values(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_ULLONG, values.data()), "H5Aread(" + name + ")");
    for (auto v : values) items.push_back(std::to_string(v));
  } else {
    std::vector<long long> values(count);
    h5::check(H5Aread(attribute.get(), H5T_NATIVE_LLONG, values.data()), "H5Aread(" + name + ")");
    for (auto v : values) items.push_back(std::to_string(v));
  }
  if (count == 1) return shownText(name) + " = " + items[0];
  for (size_t i = 0; i < items.size(); ++i) value += (i ? ", " : "") + items[i];
  return shownText(name) + " = [" + value + "]";
}

/// Every dataset in the file, by full name.
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

std::string fixed(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%14.6g", value);
  return text;
}

/// Per channel over the patches: B's least, sum and greatest, and the power emitted and
/// reflected (area times E, and times B - E); with the total area.
struct LightTotals {
  double area = 0;
  Rgb low{}, high{}, sum{}, emitted{}, reflected{};
};

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

/// A row of the summary's table: its label, then R, G and B times `scale`.
void tableRow(std::ostream& out, const char* label, const Rgb& v, double scale) {
  char text[40];
  std::snprintf(text, sizeof text, "  %-28s", label);
  out << text;
  for (int k = 0; k < 3; ++k) out << fixed(v[k] * scale);
  out << "\n";
}

/// The estimated error in the measure of io/store/light_error.h: sampling alone, and with the
/// discretisation estimate where the file has one.
void describeEstimatedError(std::ostream& out, const Result& r) {
  // Hidden patches were left out of the solve (B = E exactly): they count as reflecting nothing
  // in the error figures, as in the solve's own.
  std::vector<Rgb> rho = r.mesh.reflectance;
  for (size_t t = 0; t < r.hidden.size(); ++t)
    if (r.hidden[t]) rho[t] = Rgb{0, 0, 0};
  const size_t np = r.radiosity.size();
  tableRow(out, "estimated sampling error",
           relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, r.radiosityStderr), 1);
  if (!r.radiosityDiscretisation.empty()) {
    std::vector<Rgb> total(np);
    for (size_t i = 0; i < np; ++i)
      for (int k = 0; k < 3; ++k)
        total[i][k] = std::hypot(r.radiosityStderr[i][k], r.radiosityDiscretisation[i][k]);
    tableRow(out, "estimated error (with discr.)",
             relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, total), 1);
  }
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

/// How the solver was chosen, what made the file, and the solve's figures.
void describeSolve(std::ostream& out, const ResultAttributes& a) {
  if (!a.solverChoice.empty())
    out << "  solver choice: " << shownText(a.solverChoice, 2000) << "\n";
  if (!a.software.empty()) {
    out << "  made by:";
    for (const auto& [name, version] : a.software)
      out << " " << shownText(name) << " " << shownText(version) << ";";
    out << "\n";
  }
  if (!a.solveFigures.empty()) {
    out << "  solve figures:\n";
    for (const auto& [key, value] : a.solveFigures)
      out << "    " << format::attribute::kSolveFigurePrefix << key << " = " << exact(value)
          << "\n";
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
  out << "                                           R             G             B\n";
  tableRow(out, "radiosity min", totals.low, 1);
  tableRow(out, "radiosity mean", totals.sum, np ? 1.0 / np : 0);
  tableRow(out, "radiosity max", totals.high, 1);
  tableRow(out, "emitted power sum(A*E)", totals.emitted, 1);
  tableRow(out, "reflected power sum(A*(B-E))", totals.reflected, 1);
  if (!r.radiosityStderr.empty()) describeEstimatedError(out, r);
  describeFormFactors(out, r);
  if (r.attributes.history.size() > 0) describeHistory(out, r.attributes.history);
  describeSolve(out, r.attributes);
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
      out << "  " << attributeText(file.get(), name) << "\n";
    // A checkpoint or other HDF5 file is listed; a result is also summarised, and must be whole.
    if (exists(file.get(), format::kPatches) || exists(file.get(), format::kMesh))
      out << summaryOf(readOpenResult(file.get(), path));
  } catch (const h5::Failure& e) {
    h5::fail(path, e.what());
  }
  return out.str();
}

}  // namespace radiosity
