// Reads a result file whole on the calling process with serial HDF5 (the default file driver, so
// it works with or without MPI), and describes one for `radiosity info`. Every problem with the
// file is an InputError naming the file and, where there is one, the dataset or attribute.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "core/shown_text.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/light_error.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

/// The newest format_version this reader understands.
constexpr int kFormatVersion = 1;

using h5::exact;
using h5::exists;
using h5::fail;
using h5::narrowed;
using h5::readAttribute;
using h5::readDataset;
using h5::readString;
using h5::shapeOf;
using h5::shapeText;
using h5::typeName;

h5::Handle openFile(const std::string& path) { return h5::openFile(path, "result file"); }

template <class Row, class T>
std::vector<Row> rowsOf3(const std::vector<T>& flat) {
  std::vector<Row> rows(flat.size() / 3);
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) rows[i][k] = flat[3 * i + k];
  return rows;
}

ResultAttributes readAttributes(hid_t file, const std::string& path) {
  ResultAttributes a;
  a.formatVersion =
      narrowed<int>(readAttribute<int64_t>(file, path, "format_version"), path, "format_version");
  if (a.formatVersion > kFormatVersion || a.formatVersion < 1)
    fail(path, "format_version " + std::to_string(a.formatVersion) +
                   " is not one this program reads (1 to " + std::to_string(kFormatVersion) + ")");
  a.ranks = narrowed<int>(readAttribute<int64_t>(file, path, "ranks"), path, "ranks");
  a.raysPerPatch = readAttribute<int64_t>(file, path, "rays_per_patch");
  a.seed = readAttribute<uint64_t>(file, path, "seed");
  a.solver = readAttribute<std::string>(file, path, "solver");
  a.iterations = readAttribute<int64_t>(file, path, "iterations");
  a.residual = readAttribute<double>(file, path, "residual");
  a.converged = readAttribute<int64_t>(file, path, "converged") != 0;
  // Not among the required attributes (docs/result-format.md): a file without them is a result.
  if (H5Aexists(file, "scene") > 0) a.scene = readAttribute<std::string>(file, path, "scene");
  if (H5Aexists(file, "left_out") > 0) {
    a.leftOut = readAttribute<std::string>(file, path, "left_out");
  }
  if (H5Aexists(file, "options") > 0) a.options = readAttribute<std::string>(file, path, "options");
  for (const std::string& name : h5::attributeNames(file)) {
    if (name.rfind("time_", 0) == 0)
      a.stageSeconds[name.substr(5)] = readAttribute<double>(file, path, name);
    if (name.rfind("solve_", 0) == 0)
      a.solveFigures[name.substr(6)] = readAttribute<double>(file, path, name);
    if (name.rfind("software_", 0) == 0)
      a.software[name.substr(9)] = readAttribute<std::string>(file, path, name);
  }
  if (h5::check(H5Aexists(file, "solver_choice"), "H5Aexists(solver_choice)") > 0)
    a.solverChoice = readAttribute<std::string>(file, path, "solver_choice");
  if (h5::check(H5Aexists(file, "length_unit"), "H5Aexists(length_unit)") > 0)
    a.lengthUnit = readAttribute<std::string>(file, path, "length_unit");
  return a;
}

/// The optional /solve/history: rows of channel, iteration, residual, seconds, checked.
SolveHistory readSolveHistory(hid_t file, const std::string& path) {
  if (!exists(file, "/solve/history")) return SolveHistory{};
  return h5::readSolveHistory(file, path, "/solve/history");
}

/// The optional /groups: view factors between labels, their areas and names, checked.
void readGroups(hid_t file, const std::string& path, GroupFactors& groups) {
  if (!exists(file, "/groups/view_factors")) return;
  int64_t count = -1;
  groups.area = readDataset<double>(file, path, "/groups/area", H5T_NATIVE_DOUBLE, 0, count);
  if (count < 1 || count > (int64_t{1} << 15))
    fail(path, "dataset /groups/area has " + std::to_string(count) + " groups");
  groups.factors = readDataset<double>(file, path, "/groups/view_factors", H5T_NATIVE_DOUBLE,
                                       static_cast<int>(count), count);
  h5::Handle dataset = h5::own(H5Dopen2(file, "/groups/view_factors", H5P_DEFAULT),
                               "H5Dopen2(/groups/view_factors)");
  groups.names = h5::readStringArrayAttribute(dataset.get(), path, "names");
  if (static_cast<int64_t>(groups.names.size()) != count)
    fail(path, "attribute names of /groups/view_factors has " +
                   std::to_string(groups.names.size()) + " names for " + std::to_string(count) +
                   " groups");
}

/// The optional /formfactors group: the row-sum histogram and F in CSR form, checked.
void readFormFactors(hid_t file, const std::string& path, int64_t np, Result& result) {
  if (exists(file, "/formfactors/row_sum_histogram")) {
    int64_t bins = -1, edges = -1;
    result.rowSumHistogram = readDataset<int64_t>(file, path, "/formfactors/row_sum_histogram",
                                                  H5T_NATIVE_INT64, 0, bins);
    result.rowSumBinEdges = readDataset<double>(file, path, "/formfactors/row_sum_bin_edges",
                                                H5T_NATIVE_DOUBLE, 0, edges);
  }
  if (!exists(file, "/formfactors/row_start")) return;
  MatrixRows rows;
  int64_t starts = np + 1, nonzeros = -1;
  rows.rowStart =
      readDataset<int64_t>(file, path, "/formfactors/row_start", H5T_NATIVE_INT64, 0, starts);
  rows.column =
      readDataset<int64_t>(file, path, "/formfactors/column", H5T_NATIVE_INT64, 0, nonzeros);
  rows.value =
      readDataset<double>(file, path, "/formfactors/value", H5T_NATIVE_DOUBLE, 0, nonzeros);
  if (rows.rowStart.front() != 0 || rows.rowStart.back() != nonzeros ||
      !std::is_sorted(rows.rowStart.begin(), rows.rowStart.end()))
    fail(path, "dataset /formfactors/row_start does not run from 0 up to " +
                   std::to_string(nonzeros) + " (the length of /formfactors/column)");
  for (int64_t j : rows.column)
    if (j < 0 || j >= np)
      fail(path, "dataset /formfactors/column holds " + std::to_string(j) + ", not a patch of " +
                     std::to_string(np));
  result.formFactors = std::move(rows);
}

Result readOpenFile(hid_t file, const std::string& path) {
  Result result;
  int64_t nv = -1, np = -1;
  result.mesh.vertices =
      rowsOf3<Vec3>(readDataset<double>(file, path, "/mesh/vertices", H5T_NATIVE_DOUBLE, 3, nv));
  result.mesh.triangles = rowsOf3<Triangle>(
      readDataset<int64_t>(file, path, "/mesh/triangles", H5T_NATIVE_INT64, 3, np));
  for (size_t t = 0; t < result.mesh.triangles.size(); ++t)
    for (int64_t v : result.mesh.triangles[t])
      if (v < 0 || v >= nv)
        fail(path, "dataset /mesh/triangles: row " + std::to_string(t) + " refers to vertex " +
                       std::to_string(v) + " of " + std::to_string(nv));
  auto rgb = [&](const char* name) {
    return rowsOf3<Rgb>(readDataset<double>(file, path, name, H5T_NATIVE_DOUBLE, 3, np));
  };
  result.area = readDataset<double>(file, path, "/patches/area", H5T_NATIVE_DOUBLE, 0, np);
  result.normal =
      rowsOf3<Vec3>(readDataset<double>(file, path, "/patches/normal", H5T_NATIVE_DOUBLE, 3, np));
  result.mesh.reflectance = rgb("/patches/reflectance");
  result.mesh.emission = rgb("/patches/emission");
  result.radiosity = rgb("/patches/radiosity");
  result.irradiance = rgb("/patches/irradiance");
  // Optional: the estimated standard error of B, one finite value ≥ 0 per patch and channel.
  if (exists(file, "/patches/radiosity_stderr")) {
    result.radiosityStderr = rgb("/patches/radiosity_stderr");
    for (size_t t = 0; t < result.radiosityStderr.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const double e = result.radiosityStderr[t][k];
        if (!std::isfinite(e) || !(e >= 0))
          fail(path, "dataset /patches/radiosity_stderr: row " + std::to_string(t) + " channel " +
                         std::to_string(k) + " holds " + exact(e) + ", not a finite value >= 0");
      }
  }
  if (exists(file, "/patches/radiosity_discretisation")) {
    result.radiosityDiscretisation = rgb("/patches/radiosity_discretisation");
    for (size_t t = 0; t < result.radiosityDiscretisation.size(); ++t)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(result.radiosityDiscretisation[t][k]))
          fail(path, "dataset /patches/radiosity_discretisation: row " + std::to_string(t) +
                         " channel " + std::to_string(k) + " is not finite");
  }
  if (exists(file, "/patches/hidden")) {
    const std::vector<int8_t> hidden =
        readDataset<int8_t>(file, path, "/patches/hidden", H5T_NATIVE_INT8, 0, np);
    for (size_t t = 0; t < hidden.size(); ++t)
      if (hidden[t] != 0 && hidden[t] != 1)
        fail(path, "dataset /patches/hidden: row " + std::to_string(t) + " holds " +
                       std::to_string(hidden[t]) + ", not 0 or 1");
    result.hidden.assign(hidden.begin(), hidden.end());
  }
  result.mesh.sourceFace =
      readDataset<int64_t>(file, path, "/patches/source_face", H5T_NATIVE_INT64, 0, np);
  result.rank = readDataset<int32_t>(file, path, "/patches/rank", H5T_NATIVE_INT32, 0, np);
  result.attributes = readAttributes(file, path);
  result.attributes.history = readSolveHistory(file, path);
  readFormFactors(file, path, np, result);
  readGroups(file, path, result.groups);
  if (!result.groups.empty() && exists(file, "/patches/group")) {
    std::vector<int32_t> group =
        readDataset<int32_t>(file, path, "/patches/group", H5T_NATIVE_INT32, 0, np);
    for (int32_t g : group) {
      if (g < 0 || static_cast<size_t>(g) >= result.groups.names.size())
        fail(path, "dataset /patches/group holds " + std::to_string(g) + ", not one of the " +
                       std::to_string(result.groups.names.size()) + " groups");
    }
    result.mesh.label = std::move(group);
    result.mesh.labelNames = result.groups.names;
  }
  return result;
}

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

std::string summaryOf(const Result& r) {
  // Hidden patches were left out of the solve (B = E exactly): they count as reflecting nothing
  // in the error figures, as in the solve's own.
  std::vector<Rgb> rho = r.mesh.reflectance;
  for (size_t t = 0; t < r.hidden.size(); ++t)
    if (r.hidden[t]) rho[t] = Rgb{0, 0, 0};
  const size_t np = r.radiosity.size();
  double totalArea = 0;
  Rgb low{}, high{}, sum{}, emitted{}, reflected{};
  for (int k = 0; k < 3; ++k) {
    low[k] = np ? std::numeric_limits<double>::infinity() : 0;
    high[k] = np ? -std::numeric_limits<double>::infinity() : 0;
  }
  for (size_t i = 0; i < np; ++i) {
    totalArea += r.area[i];
    for (int k = 0; k < 3; ++k) {
      const double b = r.radiosity[i][k], e = r.mesh.emission[i][k];
      low[k] = std::min(low[k], b);
      high[k] = std::max(high[k], b);
      sum[k] += b;
      emitted[k] += r.area[i] * e;
      // B = E + ρH: what leaves a patch beyond its own emission is reflected.
      reflected[k] += r.area[i] * (b - e);
    }
  }
  std::ostringstream out;
  out << "summary:\n"
      << "  patches: " << np << "\n"
      << "  vertices: " << r.mesh.vertices.size() << "\n"
      << "  total area: " << exact(totalArea) << "\n";
  if (!r.hidden.empty()) {
    out << "  hidden patches (see nothing; left out of the solve): "
        << std::count(r.hidden.begin(), r.hidden.end(), 1) << "\n";
  }
  out << "                                           R             G             B\n";
  auto row = [&](const char* label, const Rgb& v, double scale) {
    char text[40];
    std::snprintf(text, sizeof text, "  %-28s", label);
    out << text;
    for (int k = 0; k < 3; ++k) out << fixed(v[k] * scale);
    out << "\n";
  };
  row("radiosity min", low, 1);
  row("radiosity mean", sum, np ? 1.0 / np : 0);
  row("radiosity max", high, 1);
  row("emitted power sum(A*E)", emitted, 1);
  row("reflected power sum(A*(B-E))", reflected, 1);
  if (!r.radiosityStderr.empty()) {
    // The estimated error in the measure of io/store/light_error.h: sampling alone, and with the
    // discretisation estimate where the file has one.
    row("estimated sampling error",
        relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, r.radiosityStderr), 1);
    if (!r.radiosityDiscretisation.empty()) {
      std::vector<Rgb> total(np);
      for (size_t i = 0; i < np; ++i)
        for (int k = 0; k < 3; ++k)
          total[i][k] = std::hypot(r.radiosityStderr[i][k], r.radiosityDiscretisation[i][k]);
      row("estimated error (with discr.)",
          relativeLightError(MPI_COMM_SELF, r.area, rho, r.radiosity, total), 1);
    }
    out << "    (RMS over the reflecting patches of each patch's error relative to its own B)\n";
  }
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
  const SolveHistory& history = r.attributes.history;
  if (history.size() > 0) {
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
  if (!r.attributes.solverChoice.empty())
    out << "  solver choice: " << shownText(r.attributes.solverChoice, 2000) << "\n";
  if (!r.attributes.software.empty()) {
    out << "  made by:";
    for (const auto& [name, version] : r.attributes.software)
      out << " " << shownText(name) << " " << shownText(version) << ";";
    out << "\n";
  }
  if (!r.attributes.solveFigures.empty()) {
    out << "  solve figures:\n";
    for (const auto& [key, value] : r.attributes.solveFigures)
      out << "    solve_" << key << " = " << exact(value) << "\n";
  }
  return out.str();
}

}  // namespace

Result readResult(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = openFile(path);
  try {
    return readOpenFile(file.get(), path);
  } catch (const h5::Failure& e) {
    fail(path, e.what());
  }
}

std::string describeResult(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = openFile(path);
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
    if (exists(file.get(), "/patches") || exists(file.get(), "/mesh"))
      out << summaryOf(readOpenFile(file.get(), path));
  } catch (const h5::Failure& e) {
    fail(path, e.what());
  }
  return out.str();
}

}  // namespace radiosity
