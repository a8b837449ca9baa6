// Reads a result file whole on the calling process with serial HDF5 (the default file driver, so
// it works with or without MPI). Every problem with the file is an InputError naming the file
// and, where there is one, the dataset or attribute.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "io/store/checkpoint_format.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result.h"
#include "io/store/result_format.h"
#include "io/store/result_reading.h"
#include "io/store/scene_file_format.h"

namespace radiosity {
namespace {

namespace format = result_format;

using h5::exact;
using h5::exists;
using h5::fail;
using h5::narrowed;
using h5::readAttribute;
using h5::readDataset;

h5::Handle openFile(const std::string& path) { return h5::openFile(path, "result file"); }

template <class Row, class T>
std::vector<Row> rowsOf3(const std::vector<T>& flat) {
  std::vector<Row> rows(flat.size() / 3);
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) rows[i][k] = flat[3 * i + k];
  return rows;
}

/// The part of `name` after `prefix` if it starts with it (an attribute of a family such as
/// software_<name>), else nothing.
std::optional<std::string> afterPrefix(const std::string& name, std::string_view prefix) {
  if (!name.starts_with(prefix)) return std::nullopt;
  return name.substr(prefix.size());
}

ResultAttributes readAttributes(hid_t file, const std::string& path) {
  namespace attribute = result_format::attribute;
  ResultAttributes a;
  a.formatVersion = narrowed<int>(readAttribute<int64_t>(file, path, attribute::kFormatVersion),
                                  path, attribute::kFormatVersion);
  if (a.formatVersion > format::kFormatVersion || a.formatVersion < 1)
    fail(path, std::string(attribute::kFormatVersion) + " " + std::to_string(a.formatVersion) +
                   " is not one this program reads (1 to " +
                   std::to_string(format::kFormatVersion) + ")");
  a.ranks =
      narrowed<int>(readAttribute<int64_t>(file, path, attribute::kRanks), path, attribute::kRanks);
  a.raysPerPatch = readAttribute<int64_t>(file, path, attribute::kRaysPerPatch);
  a.seed = readAttribute<uint64_t>(file, path, attribute::kSeed);
  a.solver = readAttribute<std::string>(file, path, attribute::kSolver);
  a.iterations = readAttribute<int64_t>(file, path, attribute::kIterations);
  a.residual = readAttribute<double>(file, path, attribute::kResidual);
  a.converged = readAttribute<int64_t>(file, path, attribute::kConverged) != 0;
  // Not among the required attributes (docs/result-format.md): a file without them is a result.
  if (H5Aexists(file, attribute::kScene) > 0)
    a.scene = readAttribute<std::string>(file, path, attribute::kScene);
  if (H5Aexists(file, attribute::kLeftOut) > 0)
    a.leftOut = readAttribute<std::string>(file, path, attribute::kLeftOut);
  if (H5Aexists(file, attribute::kOptions) > 0)
    a.options = readAttribute<std::string>(file, path, attribute::kOptions);
  for (const std::string& name : h5::attributeNames(file)) {
    if (const auto stage = afterPrefix(name, attribute::kStageTimePrefix))
      a.stageSeconds[*stage] = readAttribute<double>(file, path, name);
    if (const auto figure = afterPrefix(name, attribute::kSolveFigurePrefix))
      a.solveFigures[*figure] = readAttribute<double>(file, path, name);
    if (const auto software = afterPrefix(name, attribute::kSoftwarePrefix))
      a.software[*software] = readAttribute<std::string>(file, path, name);
  }
  if (h5::check(H5Aexists(file, attribute::kSolverChoice),
                std::string("H5Aexists(") + attribute::kSolverChoice + ")") > 0)
    a.solverChoice = readAttribute<std::string>(file, path, attribute::kSolverChoice);
  if (h5::check(H5Aexists(file, attribute::kLengthUnit),
                std::string("H5Aexists(") + attribute::kLengthUnit + ")") > 0)
    a.lengthUnit = readAttribute<std::string>(file, path, attribute::kLengthUnit);
  if (h5::check(H5Aexists(file, attribute::kThermal),
                std::string("H5Aexists(") + attribute::kThermal + ")") > 0)
    a.thermal = readAttribute<std::string>(file, path, attribute::kThermal);
  return a;
}

/// The columns of the per-channel datasets, from /patches/radiosity: 3, or 1 (a thermal run).
int channelsOf(hid_t file) {
  if (!exists(file, format::kRadiosity)) return 3;  // refused by name when it is read
  h5::Handle dataset = h5::own(H5Dopen2(file, format::kRadiosity, H5P_DEFAULT),
                               std::string("H5Dopen2(") + format::kRadiosity + ")");
  h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space");
  const std::vector<hsize_t> dims = h5::shapeOf(space.get());
  if (dims.size() == 2 && dims[1] == 1) return 1;
  return 3;  // anything else is checked (and refused) as [np,3]
}

/// The optional /solve/history: rows of channel, iteration, residual, seconds, checked.
SolveHistory readSolveHistory(hid_t file, const std::string& path) {
  if (!exists(file, format::kHistory)) return SolveHistory{};
  return h5::readSolveHistory(file, path, format::kHistory);
}

/// The optional /groups: view factors between labels, their areas and names, checked.
void readGroups(hid_t file, const std::string& path, GroupFactors& groups) {
  if (!exists(file, format::kViewFactors)) return;
  int64_t count = -1;
  groups.area = readDataset<double>(file, path, format::kGroupArea, H5T_NATIVE_DOUBLE, 0, count);
  if (count < 1 || count > (int64_t{1} << 15))
    fail(path, std::string("dataset ") + format::kGroupArea + " has " + std::to_string(count) +
                   " groups");
  groups.factors = readDataset<double>(file, path, format::kViewFactors, H5T_NATIVE_DOUBLE,
                                       static_cast<int>(count), count);
  if (exists(file, format::kViewFactorError))  // results written since it exists
    groups.factorError = readDataset<double>(file, path, format::kViewFactorError,
                                             H5T_NATIVE_DOUBLE, static_cast<int>(count), count);
  const std::string factors = format::kViewFactors;
  h5::Handle dataset =
      h5::own(H5Dopen2(file, factors.c_str(), H5P_DEFAULT), "H5Dopen2(" + factors + ")");
  groups.names = h5::readStringArrayAttribute(dataset.get(), path, format::attribute::kGroupNames);
  if (static_cast<int64_t>(groups.names.size()) != count)
    fail(path, std::string("attribute ") + format::attribute::kGroupNames + " of " + factors +
                   " has " + std::to_string(groups.names.size()) + " names for " +
                   std::to_string(count) + " groups");
  if (exists(file, format::kGroupHeatRate)) {  // a thermal run's
    groups.heatRate =
        readDataset<double>(file, path, format::kGroupHeatRate, H5T_NATIVE_DOUBLE, 0, count);
    groups.heatRateError =
        readDataset<double>(file, path, format::kGroupHeatRateError, H5T_NATIVE_DOUBLE, 0, count);
  }
}

/// The optional /formfactors group: the row-sum histogram and F in CSR form, checked.
void readFormFactors(hid_t file, const std::string& path, int64_t np, Result& result) {
  if (exists(file, format::kRowSumHistogram)) {
    int64_t bins = -1, edges = -1;
    result.rowSumHistogram =
        readDataset<int64_t>(file, path, format::kRowSumHistogram, H5T_NATIVE_INT64, 0, bins);
    result.rowSumBinEdges =
        readDataset<double>(file, path, format::kRowSumBinEdges, H5T_NATIVE_DOUBLE, 0, edges);
  }
  if (!exists(file, format::kRowStart)) return;
  SparseRows rows;
  int64_t starts = np + 1, nonzeros = -1;
  rows.rowStart = readDataset<int64_t>(file, path, format::kRowStart, H5T_NATIVE_INT64, 0, starts);
  rows.column = readDataset<int64_t>(file, path, format::kColumn, H5T_NATIVE_INT64, 0, nonzeros);
  rows.value = readDataset<double>(file, path, format::kValue, H5T_NATIVE_DOUBLE, 0, nonzeros);
  if (rows.rowStart.front() != 0 || rows.rowStart.back() != nonzeros ||
      !std::is_sorted(rows.rowStart.begin(), rows.rowStart.end()))
    fail(path, std::string("dataset ") + format::kRowStart + " does not run from 0 up to " +
                   std::to_string(nonzeros) + " (the length of " + format::kColumn + ")");
  for (int64_t j : rows.column)
    if (j < 0 || j >= np)
      fail(path, std::string("dataset ") + format::kColumn + " holds " + std::to_string(j) +
                     ", not a patch of " + std::to_string(np));
  result.formFactors = std::move(rows);
}

/// A per-channel dataset: [np,3] (red, green, blue), or [np,1] for a thermal run, whose one
/// channel stands for all three in memory.
std::vector<Rgb> readChannels(hid_t file, const std::string& path, const char* name, int channels,
                              int64_t& np) {
  const std::vector<double> values =
      readDataset<double>(file, path, name, H5T_NATIVE_DOUBLE, channels, np);
  if (channels == 3) return rowsOf3<Rgb>(values);
  std::vector<Rgb> rows(values.size());
  for (size_t r = 0; r < values.size(); ++r) rows[r] = Rgb{values[r], values[r], values[r]};
  return rows;
}

/// The optional estimates of B's error, checked: the standard error finite and ≥ 0, the
/// discretisation error finite.
void readErrorEstimates(hid_t file, const std::string& path, int channels, int64_t np,
                        Result& result) {
  if (exists(file, format::kRadiosityStderr)) {
    result.radiosityStderr = readChannels(file, path, format::kRadiosityStderr, channels, np);
    for (size_t t = 0; t < result.radiosityStderr.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const double e = result.radiosityStderr[t][k];
        if (!std::isfinite(e) || !(e >= 0))
          fail(path, std::string("dataset ") + format::kRadiosityStderr + ": row " +
                         std::to_string(t) + " channel " + std::to_string(k) + " holds " +
                         exact(e) + ", not a finite value >= 0");
      }
  }
  if (exists(file, format::kRadiosityDiscretisation)) {
    result.radiosityDiscretisation =
        readChannels(file, path, format::kRadiosityDiscretisation, channels, np);
    for (size_t t = 0; t < result.radiosityDiscretisation.size(); ++t)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(result.radiosityDiscretisation[t][k]))
          fail(path, std::string("dataset ") + format::kRadiosityDiscretisation + ": row " +
                         std::to_string(t) + " channel " + std::to_string(k) + " is not finite");
  }
}

/// The optional per-patch facts: hidden (0 or 1), a thermal run's temperature and flux, and
/// with /groups each patch's group, checked against the groups.
void readPatchFacts(hid_t file, const std::string& path, int64_t np, Result& result) {
  if (exists(file, format::kHidden)) {
    const std::vector<int8_t> hidden =
        readDataset<int8_t>(file, path, format::kHidden, H5T_NATIVE_INT8, 0, np);
    for (size_t t = 0; t < hidden.size(); ++t)
      if (hidden[t] != 0 && hidden[t] != 1)
        fail(path, std::string("dataset ") + format::kHidden + ": row " + std::to_string(t) +
                       " holds " + std::to_string(hidden[t]) + ", not 0 or 1");
    result.hidden.assign(hidden.begin(), hidden.end());
  }
  if (exists(file, format::kTemperature)) {
    result.temperature =
        readDataset<double>(file, path, format::kTemperature, H5T_NATIVE_DOUBLE, 0, np);
    result.netHeatFlux =
        readDataset<double>(file, path, format::kNetHeatFlux, H5T_NATIVE_DOUBLE, 0, np);
  }
  if (!result.groups.empty() && exists(file, format::kGroup)) {
    std::vector<int32_t> group =
        readDataset<int32_t>(file, path, format::kGroup, H5T_NATIVE_INT32, 0, np);
    for (int32_t g : group) {
      if (g < 0 || static_cast<size_t>(g) >= result.groups.names.size())
        fail(path, std::string("dataset ") + format::kGroup + " holds " + std::to_string(g) +
                       ", not one of the " + std::to_string(result.groups.names.size()) +
                       " groups");
    }
    result.mesh.label = std::move(group);
    result.mesh.labelNames = result.groups.names;
  }
}

}  // namespace

Result readOpenResult(hid_t file, const std::string& path) {
  // Our other files say what they are, not which result dataset they lack.
  const std::string kind = h5::kindAttribute(file);
  if (kind == checkpoint_format::kKind)
    fail(path, "a checkpoint, not a result: `radiosity solve SCENE --restart " + path +
                   "` finishes its run into a result (`radiosity info` shows what it holds)");
  if (kind == scene_format::kKind)
    fail(path, "a scene file, not a result: `radiosity solve " + path +
                   "` solves it (`radiosity info` shows what it holds)");
  Result result;
  int64_t nv = -1, np = -1;
  result.mesh.vertices =
      rowsOf3<Vec3>(readDataset<double>(file, path, format::kVertices, H5T_NATIVE_DOUBLE, 3, nv));
  result.mesh.triangles = rowsOf3<Triangle>(
      readDataset<int64_t>(file, path, format::kTriangles, H5T_NATIVE_INT64, 3, np));
  for (size_t t = 0; t < result.mesh.triangles.size(); ++t)
    for (int64_t v : result.mesh.triangles[t])
      if (v < 0 || v >= nv)
        fail(path, std::string("dataset ") + format::kTriangles + ": row " + std::to_string(t) +
                       " refers to vertex " + std::to_string(v) + " of " + std::to_string(nv));
  const int channels = channelsOf(file);
  result.area = readDataset<double>(file, path, format::kArea, H5T_NATIVE_DOUBLE, 0, np);
  result.normal =
      rowsOf3<Vec3>(readDataset<double>(file, path, format::kNormal, H5T_NATIVE_DOUBLE, 3, np));
  result.mesh.reflectance = readChannels(file, path, format::kReflectance, channels, np);
  result.mesh.emission = readChannels(file, path, format::kEmission, channels, np);
  result.radiosity = readChannels(file, path, format::kRadiosity, channels, np);
  result.irradiance = readChannels(file, path, format::kIrradiance, channels, np);
  readErrorEstimates(file, path, channels, np, result);
  result.mesh.sourceFace =
      readDataset<int64_t>(file, path, format::kSourceFace, H5T_NATIVE_INT64, 0, np);
  result.rank = readDataset<int32_t>(file, path, format::kRank, H5T_NATIVE_INT32, 0, np);
  result.attributes = readAttributes(file, path);
  result.attributes.channels = channels;
  result.attributes.history = readSolveHistory(file, path);
  readFormFactors(file, path, np, result);
  readGroups(file, path, result.groups);
  readPatchFacts(file, path, np, result);
  return result;
}

Result readResult(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = openFile(path);
  try {
    return readOpenResult(file.get(), path);
  } catch (const h5::Failure& e) {
    fail(path, e.what());
  }
}

}  // namespace radiosity
