// Writes the result file (docs/result-format.md) with parallel HDF5. Every rank writes its own
// rows of the patch datasets and a share of the vertices; only B is gathered, on rank 0, for the
// display mesh. The file and its XDMF sidecar are written under temporary names and renamed
// once complete, so `path` holds a whole result or is left alone.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "io/store/display_writer.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result.h"
#include "io/store/result_labels.h"
#include "io/store/result_space.h"
#include "io/store/space_reservation.h"
#include "io/store/xdmf.h"

namespace radiosity {
namespace {

using h5::CollectiveSteps;
using h5::Rows;

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
  h5::broadcast(comm, a.solver);
  h5::broadcast(comm, a.leftOut);
  h5::broadcast(comm, a.scene);
  h5::broadcast(comm, a.options);
  h5::broadcast(comm, a.stageSeconds);
  h5::broadcast(comm, a.solveFigures);
  h5::broadcast(comm, a.solverChoice);
  h5::broadcast(comm, a.lengthUnit);
  h5::broadcast(comm, a.software);
  h5::broadcast(comm, a.history);
  return a;
}

/// Whether any rank has a hidden patch (then /patches/hidden is written). Collective.
int anyHidden(MPI_Comm comm, const LocalSolution& local) {
  int any = std::find(local.hidden.begin(), local.hidden.end(), 1) != local.hidden.end() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

/// Checks what the ranks hold before anything is created, so that bad arguments fail on all ranks
/// together: the patch blocks must tile [0, np) in rank order, the mesh must be the same size
/// everywhere and consistent, and this rank's triangles must index existing vertices. If any rank
/// has a radiosity stderr, every rank must have one row of it per patch it owns, each value finite
/// and ≥ 0. Returns whether /patches/radiosity_stderr is to be written (the same on every rank).
/// Collective.
bool checkArguments(CollectiveSteps& steps, MPI_Comm comm, const Mesh& patches,
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
  int withStderr = local.radiosityStderr.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &withStderr, 1, MPI_INT, MPI_MAX, comm);
  int withDiscretisation = local.radiosityDiscretisation.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &withDiscretisation, 1, MPI_INT, MPI_MAX, comm);
  const int withHidden = anyHidden(comm, local);

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
    if (withStderr != 0 && local.radiosityStderr.size() != local.radiosity.size())
      fail("radiosity stderr has " + std::to_string(local.radiosityStderr.size()) +
           " rows, radiosity " + std::to_string(local.radiosity.size()) +
           " (some rank has a radiosity stderr, so every rank needs one row per patch it owns)");
    for (size_t i = 0; i < local.radiosityStderr.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const double e = local.radiosityStderr[i][k];
        if (!std::isfinite(e) || !(e >= 0))
          fail("radiosity stderr of patch " + std::to_string(local.firstPatch + int64_t(i)) +
               " channel " + std::to_string(k) + " is " + h5::exact(e) +
               ", not a finite value >= 0");
      }
    if (withDiscretisation != 0 && local.radiosityDiscretisation.size() != local.radiosity.size())
      fail("radiosity discretisation error has " +
           std::to_string(local.radiosityDiscretisation.size()) + " rows, radiosity " +
           std::to_string(local.radiosity.size()));
    for (size_t i = 0; i < local.radiosityDiscretisation.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(local.radiosityDiscretisation[i][k]))
          fail("radiosity discretisation error of patch " +
               std::to_string(local.firstPatch + int64_t(i)) + " channel " + std::to_string(k) +
               " is not finite");
    if (withHidden != 0 && local.hidden.size() != local.radiosity.size())
      fail("hidden flags for " + std::to_string(local.hidden.size()) + " patches, radiosity " +
           std::to_string(local.radiosity.size()));
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
  return withStderr != 0;
}

void writeAttributes(hid_t file, const ResultAttributes& a) {
  const int converged = a.converged ? 1 : 0;
  h5::writeAttribute(file, "format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &a.formatVersion);
  h5::writeAttribute(file, "ranks", H5T_STD_I32LE, H5T_NATIVE_INT, &a.ranks);
  h5::writeAttribute(file, "rays_per_patch", H5T_STD_I64LE, H5T_NATIVE_INT64, &a.raysPerPatch);
  h5::writeAttribute(file, "seed", H5T_STD_U64LE, H5T_NATIVE_UINT64, &a.seed);
  h5::writeStringAttribute(file, "solver", a.solver);
  h5::writeStringAttribute(file, "left_out", a.leftOut);
  h5::writeAttribute(file, "iterations", H5T_STD_I64LE, H5T_NATIVE_INT64, &a.iterations);
  h5::writeAttribute(file, "residual", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &a.residual);
  h5::writeAttribute(file, "converged", H5T_STD_I32LE, H5T_NATIVE_INT, &converged);
  h5::writeStringAttribute(file, "scene", a.scene);
  h5::writeStringAttribute(file, "options", a.options);
  for (const auto& [stage, seconds] : a.stageSeconds)
    h5::writeAttribute(file, ("time_" + stage).c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                       &seconds);
  for (const auto& [key, value] : a.solveFigures)
    h5::writeAttribute(file, ("solve_" + key).c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
  if (!a.solverChoice.empty()) h5::writeStringAttribute(file, "solver_choice", a.solverChoice);
  if (!a.lengthUnit.empty()) h5::writeStringAttribute(file, "length_unit", a.lengthUnit);
  for (const auto& [name, version] : a.software)
    h5::writeStringAttribute(file, ("software_" + name).c_str(), version);
}

/// Writes /formfactors: the row-sum histogram (rank 0's, which every rank holds) and, if given, F
/// in CSR form, each rank its own rows at the offset of the nonzeros of the ranks before it.
/// Collective.
void writeFormFactors(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer, int64_t np,
                      const FormFactorOutput& formFactors) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  h5::Handle group;
  steps.run([&] {
    group = h5::own(H5Gcreate2(file, "/formfactors", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Gcreate2(/formfactors)");
  });
  if (!formFactors.rowSumHistogram.empty()) {
    const auto bins = static_cast<int64_t>(formFactors.rowSumHistogram.size());
    const auto edges = static_cast<int64_t>(formFactors.rowSumBinEdges.size());
    h5::writeDataset(steps, file, transfer, "/formfactors/row_sum_histogram", H5T_STD_I64LE,
                     H5T_NATIVE_INT64, bins, 0, Rows{0, rank == 0 ? bins : 0},
                     formFactors.rowSumHistogram.data());
    h5::writeDataset(steps, file, transfer, "/formfactors/row_sum_bin_edges", H5T_IEEE_F64LE,
                     H5T_NATIVE_DOUBLE, edges, 0, Rows{0, rank == 0 ? edges : 0},
                     formFactors.rowSumBinEdges.data());
  }
  if (const MatrixRows* rows = formFactors.rows) {
    const int64_t nonzeros = rows->nonzeros();
    const auto [before, total] = h5::offsetsInRankOrder(comm, nonzeros);
    // Row starts become global offsets; the last rank also writes the end, row_start[np].
    const std::vector<int64_t> rowStart = h5::globalRowStarts(comm, rows->rowStart, before);
    h5::writeDataset(steps, file, transfer, "/formfactors/row_start", H5T_STD_I64LE,
                     H5T_NATIVE_INT64, np + 1, 0,
                     Rows{rows->firstRow, static_cast<int64_t>(rowStart.size())}, rowStart.data());
    h5::writeDataset(steps, file, transfer, "/formfactors/column", H5T_STD_I64LE, H5T_NATIVE_INT64,
                     total, 0, Rows{before, nonzeros}, rows->column.data());
    h5::writeDataset(steps, file, transfer, "/formfactors/value", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                     total, 0, Rows{before, nonzeros}, rows->value.data());
  }
  steps.run([&] { group.close("H5Gclose(/formfactors)"); });
}

/// /groups: the view factors between labels, area and view_factors (its attribute `names` the
/// labels). Every rank holds them; rank 0 writes the values. Collective.
void writeGroups(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                 const GroupFactors& groups) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const auto count = static_cast<int64_t>(groups.names.size());
  const Rows written{0, rank == 0 ? count : 0};
  h5::Handle group;
  steps.run([&] {
    group = h5::own(H5Gcreate2(file, "/groups", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Gcreate2(/groups)");
  });
  h5::writeDataset(steps, file, transfer, "/groups/area", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count,
                   0, written, groups.area.data());
  h5::writeDataset(steps, file, transfer, "/groups/view_factors", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                   count, static_cast<int>(count), written, groups.factors.data());
  h5::Handle dataset;
  steps.run([&] {
    dataset = h5::own(H5Dopen2(file, "/groups/view_factors", H5P_DEFAULT),
                      "H5Dopen2(/groups/view_factors)");
    h5::writeStringArrayAttribute(dataset.get(), "names", groups.names);
    dataset.close("H5Dclose(/groups/view_factors)");
    group.close("H5Gclose(/groups)");
  });
}

/// Creates `temporary` and writes everything into it; all HDF5 handles are closed on return, on
/// success and failure alike. Collective.
void writeFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& temporary,
               const Mesh& patches, const LocalSolution& local, bool withStderr,
               const ResultAttributes& attributes, const FormFactorOutput& formFactors,
               int64_t reserveBytes) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  const Rows mine{local.firstPatch, static_cast<int64_t>(local.radiosity.size())};
  const Rows myVertices{nv * rank / size, nv * (rank + 1) / size - nv * rank / size};

  // Declared first so that it is closed last: an MPI-IO file refuses to close with objects open.
  h5::ParallelFile parallel =
      h5::createParallelFile(steps, comm, temporary, /*checksummedMetadata=*/false, reserveBytes);
  h5::Handle &file = parallel.file, &transfer = parallel.transfer;
  h5::Handle meshGroup, patchGroup;
  steps.run([&] {
    meshGroup = h5::own(H5Gcreate2(file.get(), "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                        "H5Gcreate2(/mesh)");
    patchGroup = h5::own(H5Gcreate2(file.get(), "/patches", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         "H5Gcreate2(/patches)");
  });

  // Each buffer lives only while its dataset is written, to keep the peak memory low.
  const hid_t f = file.get(), x = transfer.get();
  if (steps.ok()) {
    std::vector<double> vertices = h5::flattenRows(patches.vertices, myVertices);
    h5::writeDataset(steps, f, x, "/mesh/vertices", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nv, 3,
                     myVertices, vertices.data());
  }
  if (steps.ok()) {
    std::vector<int64_t> triangles;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t)
      triangles.insert(triangles.end(), patches.triangles[t].begin(), patches.triangles[t].end());
    h5::writeDataset(steps, f, x, "/mesh/triangles", H5T_STD_I64LE, H5T_NATIVE_INT64, np, 3, mine,
                     triangles.data());
  }
  if (steps.ok()) {
    std::vector<double> area;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) area.push_back(patches.area(t));
    h5::writeDataset(steps, f, x, "/patches/area", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 0, mine,
                     area.data());
  }
  if (steps.ok()) {
    std::vector<double> normal;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) {
      const Vec3 n = patches.normal(t);
      normal.insert(normal.end(), {n.x, n.y, n.z});
    }
    h5::writeDataset(steps, f, x, "/patches/normal", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                     normal.data());
  }
  // The per-channel datasets [np,3]: this rank's rows, from `values` at `from`.
  const auto writeChannels = [&](const char* name, const std::vector<Rgb>& values, Rows from) {
    if (!steps.ok()) return;
    const std::vector<double> flat = h5::flattenRows(values, from);
    h5::writeDataset(steps, f, x, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, mine,
                     flat.data());
  };
  writeChannels("/patches/reflectance", patches.reflectance, mine);
  writeChannels("/patches/emission", patches.emission, mine);
  // The solution rows are this rank's own, indexed from 0.
  const Rows all{0, mine.count};
  writeChannels("/patches/radiosity", local.radiosity, all);
  writeChannels("/patches/irradiance", local.irradiance, all);
  if (withStderr) writeChannels("/patches/radiosity_stderr", local.radiosityStderr, all);
  int withDiscretisation = local.radiosityDiscretisation.empty() ? 0 : 1;  // (checked before)
  MPI_Allreduce(MPI_IN_PLACE, &withDiscretisation, 1, MPI_INT, MPI_MAX, comm);
  if (withDiscretisation != 0)
    writeChannels("/patches/radiosity_discretisation", local.radiosityDiscretisation, all);
  if (anyHidden(comm, local) != 0 && steps.ok()) {
    std::vector<int8_t> hidden(local.hidden.begin(), local.hidden.end());
    h5::writeDataset(steps, f, x, "/patches/hidden", H5T_STD_I8LE, H5T_NATIVE_INT8, np, 0, mine,
                     hidden.data());
  }
  if (steps.ok()) {
    std::vector<int64_t> sourceFace(patches.sourceFace.begin() + mine.first,
                                    patches.sourceFace.begin() + mine.first + mine.count);
    h5::writeDataset(steps, f, x, "/patches/source_face", H5T_STD_I64LE, H5T_NATIVE_INT64, np, 0,
                     mine, sourceFace.data());
  }
  if (steps.ok() && !formFactors.groups.empty() && patches.hasLabels()) {
    std::vector<int32_t> group(patches.label.begin() + mine.first,
                               patches.label.begin() + mine.first + mine.count);
    h5::writeDataset(steps, f, x, "/patches/group", H5T_STD_I32LE, H5T_NATIVE_INT32, np, 0, mine,
                     group.data());
  }
  if (steps.ok()) {
    std::vector<int32_t> owner(mine.count, rank);
    h5::writeDataset(steps, f, x, "/patches/rank", H5T_STD_I32LE, H5T_NATIVE_INT32, np, 0, mine,
                     owner.data());
  }
  if (steps.ok()) writeDisplayMesh(steps, comm, f, x, patches, local);
  if (steps.ok() && (!formFactors.rowSumHistogram.empty() || formFactors.rows != nullptr))
    writeFormFactors(steps, comm, f, x, np, formFactors);
  if (steps.ok() && !formFactors.groups.empty()) writeGroups(steps, comm, f, x, formFactors.groups);
  if (steps.ok() && attributes.history.size() > 0) {
    h5::Handle group;
    steps.run([&] {
      group = h5::own(H5Gcreate2(f, "/solve", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      "H5Gcreate2(/solve)");
    });
    h5::writeSolveHistory(steps, comm, f, x, "/solve", attributes.history);
    steps.run([&] { group.close("H5Gclose(/solve)"); });
  }
  steps.run([&] { writeAttributes(file.get(), attributes); });
  labelResultDatasets(steps, file.get(), attributes.lengthUnit);
  steps.run([&] {
    patchGroup.close("H5Gclose(/patches)");
    meshGroup.close("H5Gclose(/mesh)");
    // Closing is where the remaining metadata reach the disk, so its failure counts.
    file.close("H5Fclose(" + temporary + ")");
  });
  h5::releaseUnusedSpace(steps, comm, temporary);
}

}  // namespace

void stageResult(CollectiveOutputs& outputs, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes,
                 const FormFactorOutput& formFactors) {
  const MPI_Comm comm = outputs.comm();
  h5::QuietErrors quiet;
  CollectiveSteps steps(comm);
  const bool withStderr = checkArguments(steps, comm, patches, local, formFactors.rows);
  if (!steps.ok())
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());

  const ResultAttributes shared = attributesOfRankZero(comm, attributes);
  // Every rank holds rank 0's history, so all agree on whether it can be written.
  steps.run([&] { h5::checkHistory(shared.history); });
  if (!steps.ok())
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());
  // Like the attributes, the histogram is written by rank 0; the others need only its size.
  FormFactorOutput sharedFormFactors = formFactors;
  uint64_t sizes[2] = {formFactors.rowSumHistogram.size(), formFactors.rowSumBinEdges.size()};
  MPI_Bcast(sizes, 2, MPI_UINT64_T, 0, comm);
  sharedFormFactors.rowSumHistogram.resize(sizes[0]);
  sharedFormFactors.rowSumBinEdges.resize(sizes[1]);
  const int64_t reserveBytes = resultSpace(comm, patches, shared, sharedFormFactors);
  const std::string temporary = outputs.stage(path);
  writeFile(steps, comm, temporary, patches, local, withStderr, shared, sharedFormFactors,
            reserveBytes);
  // Test hook: RADIOSITY_TEST_RESULT_STALL seconds between the complete temporary and its
  // rename, so that a test can kill a rank right there.
  if (const char* stall = std::getenv("RADIOSITY_TEST_RESULT_STALL"); stall && steps.ok()) {
    const double seconds = std::strtod(stall, nullptr);
    if (seconds > 0 && seconds < 1e6)
      std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
  // The XDMF sidecar, from the complete file, staged to appear with it (rank 0 writes it).
  const std::string sidecar = xdmfPathFor(path);
  std::string sidecarTemporary;
  if (steps.ok()) sidecarTemporary = outputs.stage(sidecar);
  steps.run([&] {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (rank != 0) return;
    const std::string name = std::filesystem::path(path).filename().string();
    writeStagedText(sidecarTemporary, sidecar, xdmfFor(temporary, name).text);
  });
  if (!steps.ok()) {
    outputs.unstage(path);
    if (!sidecarTemporary.empty()) outputs.unstage(sidecar);
    throw Error(exit_code::kFailure, "cannot write result file " + path + ": " + steps.error());
  }
}

void writeResult(MPI_Comm comm, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes,
                 const FormFactorOutput& formFactors) {
  CollectiveOutputs outputs(comm);
  stageResult(outputs, path, patches, local, attributes, formFactors);
  outputs.commit();
}

}  // namespace radiosity
