// Writes the result file of CONTRACT.md with parallel HDF5. Every rank writes its own rows of the
// patch datasets and a share of the vertices; nothing is gathered. The file is written under a
// temporary name and renamed once complete, so `path` holds a whole result or is left alone.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/hdf5_util.h"
#include "io/io.h"

namespace radiosity {
namespace {

/// Runs a collective write as a sequence of steps; after each one the ranks agree whether all of
/// them succeeded. A rank that failed thus never leaves the others waiting in a collective HDF5
/// call: once a step failed anywhere, every rank skips the rest and holds the same message.
class CollectiveSteps {
 public:
  explicit CollectiveSteps(MPI_Comm comm) : comm_(comm) {
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &size_);
  }

  /// Runs `work` on this rank unless an earlier step failed; true if it succeeded on all ranks.
  /// Collective.
  template <class Work>
  bool run(Work&& work) {
    if (failed_) return false;
    std::string error;
    try {
      work();
    } catch (const std::exception& e) {
      error = e.what()[0] != '\0' ? e.what() : "unknown error";
    }
    return agree(error);
  }

  bool ok() const { return !failed_; }
  const std::string& error() const { return error_; }

 private:
  bool agree(const std::string& localError) {
    // The lowest failing rank tells the others what went wrong.
    int candidate = localError.empty() ? size_ : rank_;
    int failing = size_;
    MPI_Allreduce(&candidate, &failing, 1, MPI_INT, MPI_MIN, comm_);
    if (failing == size_) return true;
    std::string message = rank_ == failing ? localError : std::string();
    int length = static_cast<int>(message.size());
    MPI_Bcast(&length, 1, MPI_INT, failing, comm_);
    message.resize(length);
    MPI_Bcast(message.data(), length, MPI_CHAR, failing, comm_);
    error_ = size_ > 1 ? "rank " + std::to_string(failing) + ": " + message : message;
    failed_ = true;
    return false;
  }

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
  bool failed_ = false;
  std::string error_;
};

void broadcast(MPI_Comm comm, std::string& text) {
  uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
}

void broadcast(MPI_Comm comm, std::map<std::string, double>& values) {
  uint64_t count = values.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  std::vector<std::string> names;
  std::vector<double> numbers;
  for (const auto& [name, value] : values) {
    names.push_back(name);
    numbers.push_back(value);
  }
  names.resize(count);
  numbers.resize(count);
  MPI_Bcast(numbers.data(), static_cast<int>(count), MPI_DOUBLE, 0, comm);
  values.clear();
  for (uint64_t i = 0; i < count; ++i) {
    broadcast(comm, names[i]);
    values[names[i]] = numbers[i];
  }
}

/// Rank 0's history on every rank, each column at its own length (checked afterwards).
void broadcast(MPI_Comm comm, SolveHistory& history) {
  uint64_t sizes[4] = {history.channel.size(), history.iteration.size(), history.residual.size(),
                       history.seconds.size()};
  MPI_Bcast(sizes, 4, MPI_UINT64_T, 0, comm);
  history.channel.resize(sizes[0]);
  history.iteration.resize(sizes[1]);
  history.residual.resize(sizes[2]);
  history.seconds.resize(sizes[3]);
  MPI_Bcast(history.channel.data(), static_cast<int>(sizes[0]), MPI_INT, 0, comm);
  MPI_Bcast(history.iteration.data(), static_cast<int>(sizes[1]), MPI_INT64_T, 0, comm);
  MPI_Bcast(history.residual.data(), static_cast<int>(sizes[2]), MPI_DOUBLE, 0, comm);
  MPI_Bcast(history.seconds.data(), static_cast<int>(sizes[3]), MPI_DOUBLE, 0, comm);
}

/// Throws std::invalid_argument unless `history` can be stored as /solve/history and read back
/// the same: columns of one length, channels 0 to 2, iterations exact in float64.
void checkHistory(const SolveHistory& history) {
  const size_t n = history.size();
  if (history.channel.size() != n || history.iteration.size() != n || history.seconds.size() != n)
    throw std::invalid_argument("solve history has " + std::to_string(history.channel.size()) +
                                " channels, " + std::to_string(history.iteration.size()) +
                                " iterations, " + std::to_string(n) + " residuals and " +
                                std::to_string(history.seconds.size()) + " times");
  constexpr int64_t kLargestExact = int64_t{1} << 53;
  for (size_t i = 0; i < n; ++i) {
    if (history.channel[i] < 0 || history.channel[i] > 2)
      throw std::invalid_argument("solve history entry " + std::to_string(i) + " has channel " +
                                  std::to_string(history.channel[i]) + ", not 0, 1 or 2");
    if (history.iteration[i] < 0 || history.iteration[i] > kLargestExact)
      throw std::invalid_argument("solve history entry " + std::to_string(i) + " has iteration " +
                                  std::to_string(history.iteration[i]) + ", not in [0, 2^53]");
  }
}

/// HDF5 needs identical attributes on every rank, but times are measured per rank: rank 0's
/// values are the ones written.
ResultAttributes attributesOfRankZero(MPI_Comm comm, const ResultAttributes& mine) {
  ResultAttributes a = mine;
  int ints[3] = {a.formatVersion, a.ranks, a.converged ? 1 : 0};
  MPI_Bcast(ints, 3, MPI_INT, 0, comm);
  int64_t longs[2] = {a.raysPerPatch, a.iterations};
  MPI_Bcast(longs, 2, MPI_INT64_T, 0, comm);
  MPI_Bcast(&a.seed, 1, MPI_UINT64_T, 0, comm);
  MPI_Bcast(&a.residual, 1, MPI_DOUBLE, 0, comm);
  a.formatVersion = ints[0];
  a.ranks = ints[1];
  a.converged = ints[2] != 0;
  a.raysPerPatch = longs[0];
  a.iterations = longs[1];
  broadcast(comm, a.solver);
  broadcast(comm, a.leftOut);
  broadcast(comm, a.scene);
  broadcast(comm, a.options);
  broadcast(comm, a.stageSeconds);
  broadcast(comm, a.solveFigures);
  broadcast(comm, a.solverChoice);
  broadcast(comm, a.history);
  return a;
}

/// A name beside `path` that does not exist yet, chosen on rank 0 and shared. Collective.
std::string temporaryName(MPI_Comm comm, const std::string& path) {
  std::string name;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    std::random_device entropy;
    std::error_code ignored;
    do {
      char suffix[64];
      std::snprintf(suffix, sizeof suffix, ".tmp.%ld.%08x", static_cast<long>(getpid()),
                    static_cast<unsigned>(entropy()));
      name = path + suffix;
    } while (std::filesystem::exists(name, ignored));
  }
  broadcast(comm, name);
  return name;
}

/// Rows [first, first + count) of a dataset, the part one rank writes.
struct Rows {
  int64_t first = 0;
  int64_t count = 0;
};

/// Checks what the ranks hold before anything is created, so that bad arguments fail on all ranks
/// together: the patch blocks must tile [0, np) in rank order, the mesh must be the same size
/// everywhere and consistent, and this rank's triangles must index existing vertices.
/// Collective.
void checkArguments(CollectiveSteps& steps, MPI_Comm comm, const Mesh& patches,
                    const LocalSolution& local, const MatrixRows* rows) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  int64_t mine[4] = {local.firstPatch, static_cast<int64_t>(local.radiosity.size()), np, nv};
  std::vector<int64_t> all(4 * static_cast<size_t>(size));
  MPI_Allgather(mine, 4, MPI_INT64_T, all.data(), 4, MPI_INT64_T, comm);
  int withRows[2] = {rows != nullptr ? 1 : 0, rows != nullptr ? 1 : 0};
  MPI_Allreduce(MPI_IN_PLACE, &withRows[0], 1, MPI_INT, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &withRows[1], 1, MPI_INT, MPI_MAX, comm);

  steps.run([&] {
    auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
    if (local.irradiance.size() != local.radiosity.size())
      fail("irradiance has " + std::to_string(local.irradiance.size()) + " rows, radiosity " +
           std::to_string(local.radiosity.size()));
    if (patches.sourceFace.size() != patches.triangles.size() ||
        patches.reflectance.size() != patches.triangles.size() ||
        patches.emission.size() != patches.triangles.size())
      fail("mesh has " + std::to_string(np) + " triangles but " +
           std::to_string(patches.sourceFace.size()) + " source faces, " +
           std::to_string(patches.reflectance.size()) + " reflectances and " +
           std::to_string(patches.emission.size()) + " emissions");
    int64_t expectedFirst = 0;
    for (int r = 0; r < size; ++r) {
      const int64_t* row = &all[4 * static_cast<size_t>(r)];
      if (row[2] != np || row[3] != nv)
        fail("rank " + std::to_string(r) + " holds a mesh of " + std::to_string(row[2]) +
             " patches and " + std::to_string(row[3]) + " vertices, rank " + std::to_string(rank) +
             " one of " + std::to_string(np) + " and " + std::to_string(nv));
      if (row[0] != expectedFirst)
        fail("rank " + std::to_string(r) + " owns patches from " + std::to_string(row[0]) +
             " but the blocks of the ranks before it end at " + std::to_string(expectedFirst));
      expectedFirst += row[1];
    }
    if (expectedFirst != np)
      fail("the ranks own " + std::to_string(expectedFirst) + " patches of " + std::to_string(np));
    for (int64_t t = local.firstPatch; t < local.firstPatch + mine[1]; ++t)
      for (int k = 0; k < 3; ++k)
        if (patches.triangles[t][k] < 0 || patches.triangles[t][k] >= nv)
          fail("triangle " + std::to_string(t) + " refers to vertex " +
               std::to_string(patches.triangles[t][k]) + " of " + std::to_string(nv));
    if (withRows[0] != withRows[1]) fail("some ranks have rows of F to write, others not");
    if (rows == nullptr) return;
    if (rows->firstRow != local.firstPatch || rows->rowCount() != mine[1])
      fail("rows of F " + std::to_string(rows->firstRow) + " + " +
           std::to_string(rows->rowCount()) + " do not match the patches " +
           std::to_string(local.firstPatch) + " + " + std::to_string(mine[1]));
    if (rows->rowStart.front() != 0 || rows->rowStart.back() != rows->nonzeros() ||
        rows->value.size() != rows->column.size() ||
        !std::is_sorted(rows->rowStart.begin(), rows->rowStart.end()))
      fail("rows of F are not in CSR form: row starts from " +
           std::to_string(rows->rowStart.front()) + " to " + std::to_string(rows->rowStart.back()) +
           " for " + std::to_string(rows->column.size()) + " columns and " +
           std::to_string(rows->value.size()) + " values");
    for (int64_t j : rows->column)
      if (j < 0 || j >= np)
        fail("a row of F has column " + std::to_string(j) + " of " + std::to_string(np));
  });
}

/// Writes one dataset of `total` rows of `columns` values (0: a 1-D dataset) of which this rank
/// writes `rows` from `data` (row-major). Collective: every rank calls it with the same name,
/// types and total, and each step ends with the ranks agreeing on success.
void writeDataset(CollectiveSteps& steps, hid_t file, hid_t transfer, const std::string& name,
                  hid_t fileType, hid_t memoryType, int64_t total, int columns, Rows rows,
                  const void* data) {
  h5::Handle fileSpace, memorySpace, creation, dataset;
  steps.run([&] {
    const int rank = columns == 0 ? 1 : 2;
    const hsize_t dims[2] = {static_cast<hsize_t>(total), static_cast<hsize_t>(columns)};
    fileSpace = h5::own(H5Screate_simple(rank, dims, nullptr), "H5Screate_simple(" + name + ")");
    // A rank without rows still takes part in the collective write, selecting nothing.
    const hsize_t memoryDims[2] = {static_cast<hsize_t>(std::max<int64_t>(rows.count, 1)),
                                   static_cast<hsize_t>(columns)};
    memorySpace =
        h5::own(H5Screate_simple(rank, memoryDims, nullptr), "H5Screate_simple(" + name + ")");
    if (rows.count == 0) {
      h5::check(H5Sselect_none(fileSpace.get()), "H5Sselect_none(" + name + ")");
      h5::check(H5Sselect_none(memorySpace.get()), "H5Sselect_none(" + name + ")");
    } else {
      const hsize_t start[2] = {static_cast<hsize_t>(rows.first), 0};
      h5::check(
          H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start, nullptr, memoryDims, nullptr),
          "H5Sselect_hyperslab(" + name + ")");
    }
    // Every element is written, so filling the dataset first would only double the I/O.
    creation = h5::own(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate(" + name + ")");
    h5::check(H5Pset_fill_time(creation.get(), H5D_FILL_TIME_NEVER),
              "H5Pset_fill_time(" + name + ")");
  });
  steps.run([&] {
    dataset = h5::own(H5Dcreate2(file, name.c_str(), fileType, fileSpace.get(), H5P_DEFAULT,
                                 creation.get(), H5P_DEFAULT),
                      "H5Dcreate2(" + name + ")");
  });
  steps.run([&] {
    static const double kNothing[3] = {};
    // An empty dataset has no storage to write to (the same decision on every rank).
    if (total > 0)
      h5::check(H5Dwrite(dataset.get(), memoryType, memorySpace.get(), fileSpace.get(), transfer,
                         data != nullptr ? data : kNothing),
                "H5Dwrite(" + name + ")");
    dataset.close("H5Dclose(" + name + ")");
  });
}

template <class Row>
std::vector<double> flatten(const std::vector<Row>& values, Rows rows) {
  std::vector<double> flat;
  flat.reserve(3 * rows.count);
  for (int64_t i = rows.first; i < rows.first + rows.count; ++i)
    for (int k = 0; k < 3; ++k) flat.push_back(values[i][k]);
  return flat;
}

void writeAttribute(hid_t file, const char* name, hid_t fileType, hid_t memoryType,
                    const void* value) {
  const std::string what = std::string("attribute ") + name;
  h5::Handle space = h5::own(H5Screate(H5S_SCALAR), "H5Screate(" + what + ")");
  h5::Handle attribute =
      h5::own(H5Acreate2(file, name, fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "H5Acreate2(" + what + ")");
  h5::check(H5Awrite(attribute.get(), memoryType, value), "H5Awrite(" + what + ")");
  attribute.close("H5Aclose(" + what + ")");
}

void writeStringAttribute(hid_t file, const char* name, const std::string& value) {
  // Fixed length (HDF5 refuses size 0), UTF-8 so that readers such as h5py decode it to text.
  h5::Handle type = h5::own(H5Tcopy(H5T_C_S1), "H5Tcopy");
  h5::check(H5Tset_size(type.get(), std::max<size_t>(value.size(), 1)), "H5Tset_size");
  h5::check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
  h5::check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  std::string padded = value;
  padded.resize(std::max<size_t>(value.size(), 1), '\0');
  writeAttribute(file, name, type.get(), type.get(), padded.data());
}

void writeAttributes(hid_t file, const ResultAttributes& a) {
  const int converged = a.converged ? 1 : 0;
  writeAttribute(file, "format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &a.formatVersion);
  writeAttribute(file, "ranks", H5T_STD_I32LE, H5T_NATIVE_INT, &a.ranks);
  writeAttribute(file, "rays_per_patch", H5T_STD_I64LE, H5T_NATIVE_INT64, &a.raysPerPatch);
  writeAttribute(file, "seed", H5T_STD_U64LE, H5T_NATIVE_UINT64, &a.seed);
  writeStringAttribute(file, "solver", a.solver);
  writeStringAttribute(file, "left_out", a.leftOut);
  writeAttribute(file, "iterations", H5T_STD_I64LE, H5T_NATIVE_INT64, &a.iterations);
  writeAttribute(file, "residual", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &a.residual);
  writeAttribute(file, "converged", H5T_STD_I32LE, H5T_NATIVE_INT, &converged);
  writeStringAttribute(file, "scene", a.scene);
  writeStringAttribute(file, "options", a.options);
  for (const auto& [stage, seconds] : a.stageSeconds)
    writeAttribute(file, ("time_" + stage).c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &seconds);
  for (const auto& [key, value] : a.solveFigures)
    writeAttribute(file, ("solve_" + key).c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
  if (!a.solverChoice.empty()) writeStringAttribute(file, "solver_choice", a.solverChoice);
}

/// A 1-D attribute of fixed-length UTF-8 strings (h5py reads it as an array of bytes/str).
void writeStringArrayAttribute(hid_t object, const char* name,
                               const std::vector<std::string>& values) {
  const std::string what = std::string("attribute ") + name;
  size_t width = 1;
  for (const std::string& value : values) width = std::max(width, value.size());
  std::string buffer;
  for (const std::string& value : values) {
    buffer += value;
    buffer.append(width - value.size(), '\0');
  }
  h5::Handle type = h5::own(H5Tcopy(H5T_C_S1), "H5Tcopy");
  h5::check(H5Tset_size(type.get(), width), "H5Tset_size");
  h5::check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
  h5::check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  const hsize_t count = values.size();
  h5::Handle space =
      h5::own(H5Screate_simple(1, &count, nullptr), "H5Screate_simple(" + what + ")");
  h5::Handle attribute =
      h5::own(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "H5Acreate2(" + what + ")");
  h5::check(H5Awrite(attribute.get(), type.get(), buffer.data()), "H5Awrite(" + what + ")");
  attribute.close("H5Aclose(" + what + ")");
}

/// Writes /solve/history from rank 0's copy, which every rank holds, with its `columns`
/// attribute. Collective.
void writeSolveHistory(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                       const SolveHistory& history) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const auto n = static_cast<int64_t>(history.size());
  h5::Handle group;
  steps.run([&] {
    group = h5::own(H5Gcreate2(file, "/solve", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Gcreate2(/solve)");
  });
  if (steps.ok()) {
    std::vector<double> rows;
    rows.reserve(4 * history.size());
    for (size_t i = 0; i < history.size(); ++i)
      rows.insert(rows.end(), {static_cast<double>(history.channel[i]),
                               static_cast<double>(history.iteration[i]), history.residual[i],
                               history.seconds[i]});
    writeDataset(steps, file, transfer, "/solve/history", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 4,
                 Rows{0, rank == 0 ? n : 0}, rows.data());
  }
  h5::Handle dataset;
  steps.run([&] {
    dataset = h5::own(H5Dopen2(file, "/solve/history", H5P_DEFAULT), "H5Dopen2(/solve/history)");
    writeStringArrayAttribute(dataset.get(), "columns",
                              {"channel", "iteration", "residual", "seconds"});
    dataset.close("H5Dclose(/solve/history)");
  });
  steps.run([&] { group.close("H5Gclose(/solve)"); });
}

/// Writes /formfactors: the row-sum histogram (rank 0's, which every rank holds) and, if given, F
/// in CSR form, each rank its own rows at the offset of the nonzeros of the ranks before it.
/// Collective.
void writeFormFactors(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer, int64_t np,
                      const FormFactorOutput& formFactors) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  h5::Handle group;
  steps.run([&] {
    group = h5::own(H5Gcreate2(file, "/formfactors", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Gcreate2(/formfactors)");
  });
  if (!formFactors.rowSumHistogram.empty()) {
    const auto bins = static_cast<int64_t>(formFactors.rowSumHistogram.size());
    const auto edges = static_cast<int64_t>(formFactors.rowSumBinEdges.size());
    writeDataset(steps, file, transfer, "/formfactors/row_sum_histogram", H5T_STD_I64LE,
                 H5T_NATIVE_INT64, bins, 0, Rows{0, rank == 0 ? bins : 0},
                 formFactors.rowSumHistogram.data());
    writeDataset(steps, file, transfer, "/formfactors/row_sum_bin_edges", H5T_IEEE_F64LE,
                 H5T_NATIVE_DOUBLE, edges, 0, Rows{0, rank == 0 ? edges : 0},
                 formFactors.rowSumBinEdges.data());
  }
  if (const MatrixRows* rows = formFactors.rows) {
    const int64_t nonzeros = rows->nonzeros();
    int64_t before = 0, total = 0;
    MPI_Exscan(&nonzeros, &before, 1, MPI_INT64_T, MPI_SUM, comm);
    if (rank == 0) before = 0;  // MPI_Exscan leaves rank 0's result undefined
    MPI_Allreduce(&nonzeros, &total, 1, MPI_INT64_T, MPI_SUM, comm);
    // Row starts become global offsets; the last rank also writes the end, row_start[np].
    std::vector<int64_t> rowStart(rows->rowStart.begin(),
                                  rows->rowStart.end() - (rank == size - 1 ? 0 : 1));
    for (int64_t& start : rowStart) start += before;
    writeDataset(steps, file, transfer, "/formfactors/row_start", H5T_STD_I64LE, H5T_NATIVE_INT64,
                 np + 1, 0, Rows{rows->firstRow, static_cast<int64_t>(rowStart.size())},
                 rowStart.data());
    writeDataset(steps, file, transfer, "/formfactors/column", H5T_STD_I64LE, H5T_NATIVE_INT64,
                 total, 0, Rows{before, nonzeros}, rows->column.data());
    writeDataset(steps, file, transfer, "/formfactors/value", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                 total, 0, Rows{before, nonzeros}, rows->value.data());
  }
  steps.run([&] { group.close("H5Gclose(/formfactors)"); });
}

/// Creates `temporary` and writes everything into it; all HDF5 handles are closed on return, on
/// success and failure alike. Collective.
void writeFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& temporary,
               const Mesh& patches, const LocalSolution& local, const ResultAttributes& attributes,
               const FormFactorOutput& formFactors) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  const Rows mine{local.firstPatch, static_cast<int64_t>(local.radiosity.size())};
  const Rows myVertices{nv * rank / size, nv * (rank + 1) / size - nv * rank / size};

  // Declared first so that it is closed last: an MPI-IO file refuses to close with objects open.
  h5::Handle file;
  h5::Handle access, transfer, meshGroup, patchGroup;
  steps.run([&] {
    access = h5::own(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate");
    h5::check(H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio");
    // Metadata written by one rank with collective I/O instead of by every rank independently.
    h5::check(H5Pset_coll_metadata_write(access.get(), true), "H5Pset_coll_metadata_write");
    transfer = h5::own(H5Pcreate(H5P_DATASET_XFER), "H5Pcreate");
    h5::check(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio");
  });
  steps.run([&] {
    file = h5::own(H5Fcreate(temporary.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, access.get()),
                   "H5Fcreate(" + temporary + ")");
  });
  steps.run([&] {
    meshGroup = h5::own(H5Gcreate2(file.get(), "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                        "H5Gcreate2(/mesh)");
    patchGroup = h5::own(H5Gcreate2(file.get(), "/patches", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         "H5Gcreate2(/patches)");
  });

  // Each buffer lives only while its dataset is written, to keep the peak memory low.
  const hid_t f = file.get(), x = transfer.get();
  if (steps.ok()) {
    std::vector<double> vertices = flatten(patches.vertices, myVertices);
    writeDataset(steps, f, x, "/mesh/vertices", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nv, 3,
                 myVertices, vertices.data());
  }
  if (steps.ok()) {
    std::vector<int64_t> triangles;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t)
      triangles.insert(triangles.end(), patches.triangles[t].begin(), patches.triangles[t].end());
    writeDataset(steps, f, x, "/mesh/triangles", H5T_STD_I64LE, H5T_NATIVE_INT64, np, 3, mine,
                 triangles.data());
  }
  if (steps.ok()) {
    std::vector<double> area;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) area.push_back(patches.area(t));
    writeDataset(steps, f, x, "/patches/area", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 0, mine,
                 area.data());
  }
  if (steps.ok()) {
    std::vector<double> normal;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) {
      const Vec3 n = patches.normal(t);
      normal.insert(normal.end(), {n.x, n.y, n.z});
    }
    writeDataset(steps, f, x, "/patches/normal", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                 normal.data());
  }
  if (steps.ok()) {
    std::vector<double> reflectance = flatten(patches.reflectance, mine);
    writeDataset(steps, f, x, "/patches/reflectance", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3,
                 mine, reflectance.data());
  }
  if (steps.ok()) {
    std::vector<double> emission = flatten(patches.emission, mine);
    writeDataset(steps, f, x, "/patches/emission", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                 emission.data());
  }
  // The solution rows are this rank's own, indexed from 0.
  const Rows all{0, mine.count};
  if (steps.ok()) {
    std::vector<double> radiosity = flatten(local.radiosity, all);
    writeDataset(steps, f, x, "/patches/radiosity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                 radiosity.data());
  }
  if (steps.ok()) {
    std::vector<double> irradiance = flatten(local.irradiance, all);
    writeDataset(steps, f, x, "/patches/irradiance", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                 irradiance.data());
  }
  if (steps.ok()) {
    std::vector<int64_t> sourceFace(patches.sourceFace.begin() + mine.first,
                                    patches.sourceFace.begin() + mine.first + mine.count);
    writeDataset(steps, f, x, "/patches/source_face", H5T_STD_I64LE, H5T_NATIVE_INT64, np, 0, mine,
                 sourceFace.data());
  }
  if (steps.ok()) {
    std::vector<int32_t> owner(mine.count, rank);
    writeDataset(steps, f, x, "/patches/rank", H5T_STD_I32LE, H5T_NATIVE_INT32, np, 0, mine,
                 owner.data());
  }
  if (steps.ok() && (!formFactors.rowSumHistogram.empty() || formFactors.rows != nullptr))
    writeFormFactors(steps, comm, f, x, np, formFactors);
  if (steps.ok() && attributes.history.size() > 0)
    writeSolveHistory(steps, comm, f, x, attributes.history);
  steps.run([&] { writeAttributes(file.get(), attributes); });
  steps.run([&] {
    patchGroup.close("H5Gclose(/patches)");
    meshGroup.close("H5Gclose(/mesh)");
    // Closing is where the remaining metadata reach the disk, so its failure counts.
    file.close("H5Fclose(" + temporary + ")");
  });
}

}  // namespace

void writeResult(MPI_Comm comm, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes,
                 const FormFactorOutput& formFactors) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  h5::QuietErrors quiet;
  CollectiveSteps steps(comm);
  checkArguments(steps, comm, patches, local, formFactors.rows);
  if (!steps.ok())
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());

  const ResultAttributes shared = attributesOfRankZero(comm, attributes);
  // Every rank holds rank 0's history, so all agree on whether it can be written.
  steps.run([&] { checkHistory(shared.history); });
  if (!steps.ok())
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());
  // Like the attributes, the histogram is written by rank 0; the others need only its size.
  FormFactorOutput sharedFormFactors = formFactors;
  uint64_t sizes[2] = {formFactors.rowSumHistogram.size(), formFactors.rowSumBinEdges.size()};
  MPI_Bcast(sizes, 2, MPI_UINT64_T, 0, comm);
  sharedFormFactors.rowSumHistogram.resize(sizes[0]);
  sharedFormFactors.rowSumBinEdges.resize(sizes[1]);
  const std::string temporary = temporaryName(comm, path);
  writeFile(steps, comm, temporary, patches, local, shared, sharedFormFactors);
  // Every rank has closed the file (a collective) before rank 0 renames or removes it.
  MPI_Barrier(comm);
  steps.run([&] {
    if (rank != 0) return;
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw std::runtime_error("cannot rename " + temporary + ": " + error.message());
  });
  if (!steps.ok()) {
    if (rank == 0) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
    }
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());
  }
}

}  // namespace radiosity
