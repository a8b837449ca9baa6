// Reads a result file whole on the calling process with serial HDF5 (the default file driver, so
// it works with or without MPI), and describes one for `radiosity info`. Every problem with the
// file is an InputError naming the file and, where there is one, the dataset or attribute.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "io/hdf5_util.h"
#include "io/io.h"

namespace radiosity {
namespace {

/// The newest format_version this reader understands.
constexpr int kFormatVersion = 1;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

h5::Handle openFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, error)) fail(path, "is a directory, not a result file");
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
  if (isHdf5 < 0) fail(path, "cannot read: " + h5::takeErrorText());
  if (isHdf5 == 0) fail(path, "not an HDF5 file");
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) fail(path, "cannot open: " + h5::takeErrorText());
  return h5::Handle(file);
}

/// Whether the object `name` ("/a/b") exists. H5Lexists fails rather than saying no when a group
/// on the way is missing, hence the walk.
bool exists(hid_t file, const std::string& name) {
  for (size_t slash = name.find('/', 1); slash != std::string::npos;
       slash = name.find('/', slash + 1))
    if (H5Lexists(file, name.substr(0, slash).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
}

/// "float64", "int32", "uint64", "string"...: the names CONTRACT.md uses.
std::string typeName(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type));
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits;
    case H5T_FLOAT:
      return "float" + bits;
    case H5T_STRING:
      return "string";
    case H5T_COMPOUND:
      return "compound";
    case H5T_ARRAY:
      return "array";
    case H5T_ENUM:
      return "enum";
    default:
      return "other";
  }
}

std::vector<hsize_t> shapeOf(hid_t space) {
  const int rank = h5::check(H5Sget_simple_extent_ndims(space), "H5Sget_simple_extent_ndims");
  std::vector<hsize_t> dims(rank);
  h5::check(H5Sget_simple_extent_dims(space, dims.data(), nullptr), "H5Sget_simple_extent_dims");
  return dims;
}

std::string shapeText(const std::vector<hsize_t>& dims) {
  std::string text = "[";
  for (size_t i = 0; i < dims.size(); ++i) text += (i ? ", " : "") + std::to_string(dims[i]);
  return text + "]";
}

/// The shortest text that reads back as the same double.
std::string exact(double value) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

/// The values of dataset `name`: `rows` rows (found from the file if negative) of `columns`
/// values each (0: a 1-D dataset), of the class of `memoryType` (float or integer), converted to
/// `memoryType`.
template <class T>
std::vector<T> readDataset(hid_t file, const std::string& path, const std::string& name,
                           hid_t memoryType, int columns, int64_t& rows) {
  if (!exists(file, name)) fail(path, "missing dataset " + name);
  h5::Handle dataset = h5::own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  h5::Handle type = h5::own(H5Dget_type(dataset.get()), "H5Dget_type(" + name + ")");
  h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space(" + name + ")");
  const bool wantFloat = H5Tget_class(memoryType) == H5T_FLOAT;
  const std::string wanted = (wantFloat ? "float" : "int") + std::to_string(8 * sizeof(T));
  if (H5Tget_class(type.get()) != (wantFloat ? H5T_FLOAT : H5T_INTEGER))
    fail(path, "dataset " + name + " holds " + typeName(type.get()) + ", expected " + wanted);
  const std::vector<hsize_t> dims = shapeOf(space.get());
  std::string expected = "[";
  expected += rows < 0 ? std::string("n") : std::to_string(rows);
  if (columns != 0) expected.append(", ").append(std::to_string(columns));
  expected += "]";
  if (dims.size() != (columns == 0 ? 1u : 2u) || (columns != 0 && dims[1] != hsize_t(columns)) ||
      (rows >= 0 && dims[0] != hsize_t(rows)))
    fail(path, "dataset " + name + " has shape " + shapeText(dims) + ", expected " + expected);
  rows = static_cast<int64_t>(dims[0]);
  std::vector<T> values(dims[0] * std::max(columns, 1));
  if (!values.empty())
    h5::check(H5Dread(dataset.get(), memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              "H5Dread(" + name + ")");
  return values;
}

template <class Row, class T>
std::vector<Row> rowsOf3(const std::vector<T>& flat) {
  std::vector<Row> rows(flat.size() / 3);
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) rows[i][k] = flat[3 * i + k];
  return rows;
}

std::vector<std::string> rootAttributeNames(hid_t file) {
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->push_back(name);
    return 0;
  };
  hsize_t index = 0;
  h5::check(H5Aiterate2(file, H5_INDEX_NAME, H5_ITER_INC, &index, collect, &names), "H5Aiterate2");
  return names;
}

/// A string attribute, fixed or variable length, without its padding.
std::string readString(hid_t attribute, hid_t type, const std::string& what) {
  if (h5::check(H5Tis_variable_str(type), "H5Tis_variable_str(" + what + ")") > 0) {
    h5::Handle memory = h5::own(H5Tcopy(H5T_C_S1), "H5Tcopy");
    h5::check(H5Tset_size(memory.get(), H5T_VARIABLE), "H5Tset_size");
    char* value = nullptr;
    h5::check(H5Aread(attribute, memory.get(), &value), "H5Aread(" + what + ")");
    std::string text = value != nullptr ? value : "";
    H5free_memory(value);
    return text;
  }
  h5::Handle memory = h5::own(H5Tcopy(type), "H5Tcopy");
  std::string text(H5Tget_size(type), '\0');
  h5::check(H5Aread(attribute, memory.get(), text.data()), "H5Aread(" + what + ")");
  text.resize(std::min(text.size(), text.find('\0')));
  if (H5Tget_strpad(type) == H5T_STR_SPACEPAD) text.erase(text.find_last_not_of(' ') + 1);
  return text;
}

/// A root attribute that holds one value, as int64, uint64, double or std::string.
template <class T>
T readAttribute(hid_t file, const std::string& path, const std::string& name) {
  const std::string what = "attribute " + name;
  if (h5::check(H5Aexists(file, name.c_str()), "H5Aexists(" + name + ")") <= 0)
    fail(path, "missing root attribute " + name);
  h5::Handle attribute = h5::own(H5Aopen(file, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  h5::Handle type = h5::own(H5Aget_type(attribute.get()), "H5Aget_type(" + name + ")");
  h5::Handle space = h5::own(H5Aget_space(attribute.get()), "H5Aget_space(" + name + ")");
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    fail(path, what + " holds " + std::to_string(H5Sget_simple_extent_npoints(space.get())) +
                   " values, expected one");
  const H5T_class_t typeClass = H5Tget_class(type.get());
  if constexpr (std::is_same_v<T, std::string>) {
    if (typeClass != H5T_STRING) fail(path, what + " is " + typeName(type.get()) + ", not text");
    return readString(attribute.get(), type.get(), what);
  } else {
    const bool wantFloat = std::is_floating_point_v<T>;
    if (typeClass != (wantFloat ? H5T_FLOAT : H5T_INTEGER))
      fail(path, what + " is " + typeName(type.get()) + ", expected " +
                     (wantFloat ? "a floating-point number" : "an integer"));
    const hid_t memory = wantFloat             ? H5T_NATIVE_DOUBLE
                         : std::is_signed_v<T> ? H5T_NATIVE_INT64
                                               : H5T_NATIVE_UINT64;
    T value{};
    if (H5Aread(attribute.get(), memory, &value) < 0)
      fail(path, "cannot read " + what + " as " + (wantFloat ? "float64" : typeName(memory)) +
                     ": " + h5::takeErrorText());
    return value;
  }
}

template <class Narrow>
Narrow narrowed(int64_t value, const std::string& path, const std::string& name) {
  if (value < std::numeric_limits<Narrow>::min() || value > std::numeric_limits<Narrow>::max())
    fail(path, "attribute " + name + " = " + std::to_string(value) + " is out of range");
  return static_cast<Narrow>(value);
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
  // Not among the attributes CONTRACT.md requires, so a file without them is still a result.
  if (H5Aexists(file, "scene") > 0) a.scene = readAttribute<std::string>(file, path, "scene");
  if (H5Aexists(file, "left_out") > 0) {
    a.leftOut = readAttribute<std::string>(file, path, "left_out");
  }
  if (H5Aexists(file, "options") > 0) a.options = readAttribute<std::string>(file, path, "options");
  for (const std::string& name : rootAttributeNames(file)) {
    if (name.rfind("time_", 0) == 0)
      a.stageSeconds[name.substr(5)] = readAttribute<double>(file, path, name);
    if (name.rfind("solve_", 0) == 0)
      a.solveFigures[name.substr(6)] = readAttribute<double>(file, path, name);
  }
  if (h5::check(H5Aexists(file, "solver_choice"), "H5Aexists(solver_choice)") > 0)
    a.solverChoice = readAttribute<std::string>(file, path, "solver_choice");
  return a;
}

/// The optional /solve/history: rows of channel, iteration, residual, seconds, checked.
SolveHistory readSolveHistory(hid_t file, const std::string& path) {
  SolveHistory history;
  if (!exists(file, "/solve/history")) return history;
  int64_t n = -1;
  const std::vector<double> rows =
      readDataset<double>(file, path, "/solve/history", H5T_NATIVE_DOUBLE, 4, n);
  constexpr double kLargestExact = 9007199254740992.0;  // 2^53
  for (int64_t i = 0; i < n; ++i) {
    const double channel = rows[4 * i], iteration = rows[4 * i + 1];
    if (channel != 0 && channel != 1 && channel != 2)
      fail(path, "dataset /solve/history: row " + std::to_string(i) + " has channel " +
                     exact(channel) + ", not 0, 1 or 2");
    if (!(iteration >= 0 && iteration <= kLargestExact) || iteration != std::floor(iteration))
      fail(path, "dataset /solve/history: row " + std::to_string(i) + " has iteration " +
                     exact(iteration) + ", not a whole number from 0 to 2^53");
    history.channel.push_back(static_cast<int>(channel));
    history.iteration.push_back(static_cast<int64_t>(iteration));
    history.residual.push_back(rows[4 * i + 2]);
    history.seconds.push_back(rows[4 * i + 3]);
  }
  return history;
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
  result.mesh.sourceFace =
      readDataset<int64_t>(file, path, "/patches/source_face", H5T_NATIVE_INT64, 0, np);
  result.rank = readDataset<int32_t>(file, path, "/patches/rank", H5T_NATIVE_INT32, 0, np);
  result.attributes = readAttributes(file, path);
  result.attributes.history = readSolveHistory(file, path);
  readFormFactors(file, path, np, result);
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
    if (text.find('\n') == std::string::npos) return name + " = \"" + text + "\"";
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) value += "\n      " + line;
    return name + " =" + value;
  }
  if ((typeClass != H5T_INTEGER && typeClass != H5T_FLOAT) || count < 1)
    return name + " : " + typeName(type.get()) + " " + shapeText(shapeOf(space.get()));
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
  if (count == 1) return name + " = " + items[0];
  for (size_t i = 0; i < items.size(); ++i) value += (i ? ", " : "") + items[i];
  return name + " = [" + value + "]";
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
      << "  total area: " << exact(totalArea) << "\n"
      << "                                           R             G             B\n";
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
    static const char* const kChannels[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
      // The channel's last entry in the history (channels are validated to be 0 to 2).
      for (size_t i = history.size(); i-- > 0;) {
        if (history.channel[i] != c) continue;
        out << "    " << kChannels[c] << ": last iteration " << history.iteration[i]
            << ", residual " << exact(history.residual[i]) << ", at " << exact(history.seconds[i])
            << " s\n";
        break;
      }
    }
  }
  if (!r.attributes.solverChoice.empty())
    out << "  solver choice: " << r.attributes.solverChoice << "\n";
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
      std::snprintf(line, sizeof line, "  %-24s %-8s %s\n", name.c_str(),
                    typeName(type.get()).c_str(), shapeText(shapeOf(space.get())).c_str());
      out << line;
    }
    out << "attributes:\n";
    for (const std::string& name : rootAttributeNames(file.get()))
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
