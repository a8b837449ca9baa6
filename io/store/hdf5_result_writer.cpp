// Writes the result file (docs/result-format.md) with parallel HDF5. Every rank writes its own
// rows of the patch datasets and a share of the vertices; only B is gathered, on rank 0, for the
// display mesh. The file and its XDMF sidecar are written under temporary names and renamed
// once complete, so `path` holds a whole result or is left alone.
#include <chrono>
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
#include "io/store/result_checks.h"
#include "io/store/result_format.h"
#include "io/store/result_labels.h"
#include "io/store/result_space.h"
#include "io/store/space_reservation.h"
#include "io/store/xdmf.h"

namespace radiosity {
namespace {

namespace format = result_format;
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
  h5::broadcast(comm, a.thermal);
  MPI_Bcast(&a.channels, 1, MPI_INT, 0, comm);
  h5::broadcast(comm, a.software);
  h5::broadcast(comm, a.history);
  return a;
}

void writeAttributes(hid_t file, const ResultAttributes& a) {
  namespace attribute = result_format::attribute;
  const int converged = a.converged ? 1 : 0;
  h5::writeAttribute(file, attribute::kFormatVersion, H5T_STD_I32LE, H5T_NATIVE_INT,
                     &a.formatVersion);
  h5::writeAttribute(file, attribute::kRanks, H5T_STD_I32LE, H5T_NATIVE_INT, &a.ranks);
  h5::writeAttribute(file, attribute::kRaysPerPatch, H5T_STD_I64LE, H5T_NATIVE_INT64,
                     &a.raysPerPatch);
  h5::writeAttribute(file, attribute::kSeed, H5T_STD_U64LE, H5T_NATIVE_UINT64, &a.seed);
  h5::writeStringAttribute(file, attribute::kSolver, a.solver);
  h5::writeStringAttribute(file, attribute::kLeftOut, a.leftOut);
  h5::writeAttribute(file, attribute::kIterations, H5T_STD_I64LE, H5T_NATIVE_INT64, &a.iterations);
  h5::writeAttribute(file, attribute::kResidual, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &a.residual);
  h5::writeAttribute(file, attribute::kConverged, H5T_STD_I32LE, H5T_NATIVE_INT, &converged);
  h5::writeStringAttribute(file, attribute::kScene, a.scene);
  h5::writeStringAttribute(file, attribute::kOptions, a.options);
  for (const auto& [stage, seconds] : a.stageSeconds)
    h5::writeAttribute(file, (attribute::kStageTimePrefix + stage).c_str(), H5T_IEEE_F64LE,
                       H5T_NATIVE_DOUBLE, &seconds);
  for (const auto& [key, value] : a.solveFigures)
    h5::writeAttribute(file, (attribute::kSolveFigurePrefix + key).c_str(), H5T_IEEE_F64LE,
                       H5T_NATIVE_DOUBLE, &value);
  if (!a.solverChoice.empty())
    h5::writeStringAttribute(file, attribute::kSolverChoice, a.solverChoice);
  if (!a.lengthUnit.empty()) h5::writeStringAttribute(file, attribute::kLengthUnit, a.lengthUnit);
  if (!a.thermal.empty()) h5::writeStringAttribute(file, attribute::kThermal, a.thermal);
  for (const auto& [name, version] : a.software)
    h5::writeStringAttribute(file, (attribute::kSoftwarePrefix + name).c_str(), version);
}

/// F's nonzeros the result's /formfactors/{column,value} take at a time from a store (32 MB of
/// them, as much again in HDF5's buffers: small beside F).
constexpr int64_t kNonzerosPerPiece = int64_t{1} << 21;

/// /formfactors/{row_start,column,value} from F's one store, its values rebuilt as rows a piece
/// at a time, the same number of pieces on every rank (the writes are collective).
void writeStoredFormFactors(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                            int64_t np, const SplitRows& store) {
  const std::vector<int64_t> rowStart = store.tallyRowStart();  // the rows values() gives
  const auto [before, total] = h5::offsetsInRankOrder(comm, rowStart.back());
  const std::vector<int64_t> globalStart = h5::globalRowStarts(comm, rowStart, before);
  h5::writeDataset(
      steps, file, transfer, {format::kRowStart, H5T_STD_I64LE, H5T_NATIVE_INT64, np + 1, 0},
      Rows{store.firstRow, static_cast<int64_t>(globalStart.size())}, globalStart.data());
  h5::Handle column, value;
  steps.run([&] {
    column = h5::createVectorDataset(file, format::kColumn, H5T_STD_I64LE, total,
                                     h5::Layout::kContiguous);
    value = h5::createVectorDataset(file, format::kValue, H5T_IEEE_F64LE, total,
                                    h5::Layout::kContiguous);
  });
  h5::writePieces(steps, comm, rowStart, total, kNonzerosPerPiece, [&](int64_t from, int64_t to) {
    const SparseRows piece = store.values(from, to);
    const int64_t first = before + rowStart[from];
    if (piece.nonzeros() != rowStart[to] - rowStart[from])  // (tallyRowStart's count is off)
      throw std::logic_error("rows of F " + std::to_string(from) + " to " + std::to_string(to) +
                             " do not hold the entries their starts count");
    h5::writeSlab(column.get(), format::kColumn, transfer, H5T_NATIVE_INT64, first,
                  piece.nonzeros(), piece.column.data());
    h5::writeSlab(value.get(), format::kValue, transfer, H5T_NATIVE_DOUBLE, first, piece.nonzeros(),
                  piece.value.data());
  });
  steps.run([&] {
    column.close(std::string("H5Dclose(") + format::kColumn + ")");
    value.close(std::string("H5Dclose(") + format::kValue + ")");
  });
}

/// Writes /formfactors: the row-sum histogram (rank 0's, which every rank holds) and, if given, F
/// in CSR form, each rank its own rows at the offset of the nonzeros of the ranks before it.
/// Collective.
void writeFormFactors(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer, int64_t np,
                      const FormFactorOutput& formFactors) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  h5::Handle group;
  steps.run([&] { group = h5::createGroup(file, format::kFormFactors); });
  if (!formFactors.rowSumHistogram.empty()) {
    const auto bins = static_cast<int64_t>(formFactors.rowSumHistogram.size());
    const auto edges = static_cast<int64_t>(formFactors.rowSumBinEdges.size());
    h5::writeDataset(steps, file, transfer,
                     {format::kRowSumHistogram, H5T_STD_I64LE, H5T_NATIVE_INT64, bins, 0},
                     Rows{0, rank == 0 ? bins : 0}, formFactors.rowSumHistogram.data());
    h5::writeDataset(steps, file, transfer,
                     {format::kRowSumBinEdges, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, edges, 0},
                     Rows{0, rank == 0 ? edges : 0}, formFactors.rowSumBinEdges.data());
  }
  if (formFactors.store != nullptr) {
    writeStoredFormFactors(steps, comm, file, transfer, np, *formFactors.store);
  } else if (const SparseRows* rows = formFactors.rows) {
    const int64_t nonzeros = rows->nonzeros();
    const auto [before, total] = h5::offsetsInRankOrder(comm, nonzeros);
    // Row starts become global offsets; the last rank also writes the end, row_start[np].
    const std::vector<int64_t> rowStart = h5::globalRowStarts(comm, rows->rowStart, before);
    h5::writeDataset(steps, file, transfer,
                     {format::kRowStart, H5T_STD_I64LE, H5T_NATIVE_INT64, np + 1, 0},
                     Rows{rows->firstRow, static_cast<int64_t>(rowStart.size())}, rowStart.data());
    h5::writeDataset(steps, file, transfer,
                     {format::kColumn, H5T_STD_I64LE, H5T_NATIVE_INT64, total, 0},
                     Rows{before, nonzeros}, rows->column.data());
    h5::writeDataset(steps, file, transfer,
                     {format::kValue, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, total, 0},
                     Rows{before, nonzeros}, rows->value.data());
  }
  steps.run([&] { group.close(std::string("H5Gclose(") + format::kFormFactors + ")"); });
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
  steps.run([&] { group = h5::createGroup(file, format::kGroups); });
  h5::writeDataset(steps, file, transfer,
                   {format::kGroupArea, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count, 0}, written,
                   groups.area.data());
  h5::writeDataset(
      steps, file, transfer,
      {format::kViewFactors, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count, static_cast<int>(count)},
      written, groups.factors.data());
  if (!groups.factorError.empty())
    h5::writeDataset(steps, file, transfer,
                     {format::kViewFactorError, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count,
                      static_cast<int>(count)},
                     written, groups.factorError.data());
  h5::Handle dataset;
  steps.run([&] {
    const std::string name = format::kViewFactors;
    dataset = h5::own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
    h5::writeStringArrayAttribute(dataset.get(), format::attribute::kGroupNames, groups.names);
    dataset.close("H5Dclose(" + name + ")");
  });
  if (!groups.heatRate.empty()) {
    h5::writeDataset(steps, file, transfer,
                     {format::kGroupHeatRate, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count, 0}, written,
                     groups.heatRate.data());
    h5::writeDataset(steps, file, transfer,
                     {format::kGroupHeatRateError, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, count, 0},
                     written, groups.heatRateError.data());
  }
  steps.run([&] { group.close(std::string("H5Gclose(") + format::kGroups + ")"); });
}

/// /solve: the convergence history (rank 0's, which every rank holds). Collective.
void writeSolve(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                const SolveHistory& history) {
  h5::Handle group;
  steps.run([&] { group = h5::createGroup(file, format::kSolve); });
  h5::writeSolveHistory(steps, comm, file, transfer, format::kHistory, history);
  steps.run([&] { group.close(std::string("H5Gclose(") + format::kSolve + ")"); });
}

/// /mesh: every rank writes a share of the vertices and the triangles of its own patches.
/// Collective.
void writeMesh(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
               const Mesh& patches, Rows mine) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  const Rows myVertices{nv * rank / size, nv * (rank + 1) / size - nv * rank / size};
  // (the mesh's arrays in place, without copies: the end of a run is near its memory peak)
  h5::writeDataset(steps, file, transfer,
                   {format::kVertices, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nv, 3}, myVertices,
                   h5::rowsInPlace<double>(std::span<const Vec3>(patches.vertices), myVertices));
  h5::writeDataset(steps, file, transfer,
                   {format::kTriangles, H5T_STD_I64LE, H5T_NATIVE_INT64, np, 3}, mine,
                   h5::rowsInPlace<int64_t>(std::span<const Triangle>(patches.triangles), mine));
}

/// Writes the datasets of /patches, one row per patch: this rank's rows `mine` of `np`. Each
/// buffer lives only while its dataset is written, to keep the peak memory low. Collective.
struct PatchRowsWriter {
  CollectiveSteps& steps;
  hid_t file, transfer;
  int64_t np;
  Rows mine;
  int channelCount = 3;  ///< columns of the per-channel datasets: the first channels of each Rgb

  /// `values`: this rank's rows of `columns` values each (0: one value a row).
  void write(const char* name, hid_t fileType, hid_t memoryType, int columns,
             const void* values) const {
    h5::writeDataset(steps, file, transfer, {name, fileType, memoryType, np, columns}, mine,
                     values);
  }
  /// A per-channel dataset [np,channelCount]: this rank's rows, from `values` at `from`.
  void channels(const char* name, const std::vector<Rgb>& values, Rows from) const {
    if (!steps.ok()) return;
    const std::vector<double> flat = h5::flattenColumns(values, from, channelCount);
    write(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, channelCount, flat.data());
  }
};

/// /patches/area, /patches/normal.
void writePatchGeometry(const PatchRowsWriter& out, const Mesh& patches) {
  const Rows mine = out.mine;
  if (out.steps.ok()) {
    std::vector<double> area;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) area.push_back(patches.area(t));
    out.write(format::kArea, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, area.data());
  }
  if (out.steps.ok()) {
    std::vector<double> normal;
    for (int64_t t = mine.first; t < mine.first + mine.count; ++t) {
      const Vec3 n = patches.normal(t);
      normal.insert(normal.end(), {n.x, n.y, n.z});
    }
    out.write(format::kNormal, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 3, normal.data());
  }
}

/// The per-channel datasets: ρ and E, and the solution B, H and its error estimates. Collective.
void writePatchLight(const PatchRowsWriter& out, MPI_Comm comm, const Mesh& patches,
                     const LocalSolution& local, bool withStderr) {
  out.channels(format::kReflectance, patches.reflectance, out.mine);
  out.channels(format::kEmission, patches.emission, out.mine);
  // The solution rows are this rank's own, indexed from 0.
  const Rows all{0, out.mine.count};
  out.channels(format::kRadiosity, local.radiosity, all);
  out.channels(format::kIrradiance, local.irradiance, all);
  if (withStderr) out.channels(format::kRadiosityStderr, local.radiosityStderr, all);
  int withDiscretisation = local.radiosityDiscretisation.empty() ? 0 : 1;  // (checked before)
  MPI_Allreduce(MPI_IN_PLACE, &withDiscretisation, 1, MPI_INT, MPI_MAX, comm);
  if (withDiscretisation != 0)
    out.channels(format::kRadiosityDiscretisation, local.radiosityDiscretisation, all);
  int thermal = local.temperature.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &thermal, 1, MPI_INT, MPI_MAX, comm);
  if (thermal != 0 && out.steps.ok()) {
    out.write(format::kTemperature, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, local.temperature.data());
    out.write(format::kNetHeatFlux, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, local.netHeatFlux.data());
  }
}

/// What each patch is besides its light: hidden, source face, group and owning rank. Collective.
void writePatchFacts(const PatchRowsWriter& out, MPI_Comm comm, const Mesh& patches,
                     const LocalSolution& local, bool withGroups) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const Rows mine = out.mine;
  if (anyHiddenPatch(comm, local) != 0 && out.steps.ok()) {
    std::vector<int8_t> hidden(local.hidden.begin(), local.hidden.end());
    out.write(format::kHidden, H5T_STD_I8LE, H5T_NATIVE_INT8, 0, hidden.data());
  }
  if (out.steps.ok()) {
    std::vector<int64_t> sourceFace(patches.sourceFace.begin() + mine.first,
                                    patches.sourceFace.begin() + mine.first + mine.count);
    out.write(format::kSourceFace, H5T_STD_I64LE, H5T_NATIVE_INT64, 0, sourceFace.data());
  }
  if (out.steps.ok() && withGroups && patches.hasLabels()) {
    std::vector<int32_t> group(patches.label.begin() + mine.first,
                               patches.label.begin() + mine.first + mine.count);
    out.write(format::kGroup, H5T_STD_I32LE, H5T_NATIVE_INT32, 0, group.data());
  }
  if (out.steps.ok()) {
    std::vector<int32_t> owner(mine.count, rank);
    out.write(format::kRank, H5T_STD_I32LE, H5T_NATIVE_INT32, 0, owner.data());
  }
}

/// What the result file holds: the patches, this rank's part of the solution, the run's
/// attributes and form factors (rank 0's where the ranks must agree), and whether B's standard
/// errors go in.
struct ResultContents {
  const Mesh& patches;
  const LocalSolution& local;
  const ResultAttributes& attributes;
  const FormFactorOutput& formFactors;
  bool withStderr = false;
};

/// Creates `temporary` and writes everything into it; all HDF5 handles are closed on return, on
/// success and failure alike. Collective.
void writeFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& temporary,
               const ResultContents& contents, int64_t reserveBytes) {
  const Mesh& patches = contents.patches;
  const LocalSolution& local = contents.local;
  const ResultAttributes& attributes = contents.attributes;
  const FormFactorOutput& formFactors = contents.formFactors;
  const int64_t np = patches.triangleCount();
  const Rows mine{local.firstPatch, static_cast<int64_t>(local.radiosity.size())};

  // Declared first so that it is closed last: an MPI-IO file refuses to close with objects open.
  h5::ParallelFile parallel =
      h5::createParallelFile(steps, comm, temporary, /*checksummedMetadata=*/false, reserveBytes);
  h5::Handle &file = parallel.file, &transfer = parallel.transfer;
  h5::Handle meshGroup, patchGroup;
  steps.run([&] {
    meshGroup = h5::createGroup(file.get(), format::kMesh);
    patchGroup = h5::createGroup(file.get(), format::kPatches);
  });

  const hid_t f = file.get(), x = transfer.get();
  writeMesh(steps, comm, f, x, patches, mine);
  const PatchRowsWriter patchRows{steps, f, x, np, mine, attributes.channels};
  writePatchGeometry(patchRows, patches);
  writePatchLight(patchRows, comm, patches, local, contents.withStderr);
  writePatchFacts(patchRows, comm, patches, local, !formFactors.groups.empty());
  if (steps.ok()) writeDisplayMesh(steps, comm, f, x, patches, local, attributes.channels);
  if (steps.ok() && (!formFactors.rowSumHistogram.empty() || formFactors.rows != nullptr ||
                     formFactors.store != nullptr))
    writeFormFactors(steps, comm, f, x, np, formFactors);
  if (steps.ok() && !formFactors.groups.empty()) writeGroups(steps, comm, f, x, formFactors.groups);
  if (steps.ok() && attributes.history.size() > 0)
    writeSolve(steps, comm, f, x, attributes.history);
  steps.run([&] { writeAttributes(file.get(), attributes); });
  labelResultDatasets(steps, file.get(), attributes.lengthUnit, !attributes.thermal.empty());
  steps.run([&] {
    patchGroup.close(std::string("H5Gclose(") + format::kPatches + ")");
    meshGroup.close(std::string("H5Gclose(") + format::kMesh + ")");
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
  const bool withStderr =
      checkResultArguments(steps, comm, patches, local, formFactors.rows, formFactors.store);
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
  writeFile(steps, comm, temporary, {patches, local, shared, sharedFormFactors, withStderr},
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
