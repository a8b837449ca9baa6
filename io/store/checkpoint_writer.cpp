// Writes the checkpoint of an interrupted `radiosity solve` with parallel HDF5 (layout in
// io/store/checkpoint_format.h): every rank writes its own rows of the tally and of B, nothing is
// gathered; what every rank holds alike (stage, identity, channel states, history) is rank 0's.
// Like the result file it is written under a temporary name, synced, and renamed once complete,
// so killing the job at any moment leaves an existing checkpoint at `path` as it was.
//
// Every dataset is chunked with HDF5's Fletcher32 filter. Parallel HDF5 (>= 1.10.2) writes
// filtered datasets only with collective transfers, which is what every write here is (a rank
// without rows takes part selecting nothing).
//
// An empty Checkpoint::radiosity is taken as zeros for all of the rank's rows (a checkpoint
// written before the solve started); otherwise it must have one entry per row. The samples
// behind the rows are Checkpoint::rowSamples, one count per row (rows may differ);
// rows.samples is not written.
//
// Test hook: if the environment variable RADIOSITY_TEST_CHECKPOINT_STALL holds a number of
// seconds, every rank sleeps that long once all data are in the temporary file and before it is
// closed and renamed, so that an end-to-end test can kill the job in the middle of writing a
// checkpoint.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/channels.h"
#include "core/error.h"
#include "core/matrix_rows.h"
#include "io/store/checkpoint.h"
#include "io/store/checkpoint_format.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/hdf5_util.h"
#include "io/store/rank_blocks.h"
#include "io/store/result.h"
#include "io/store/space_reservation.h"

namespace radiosity {
namespace {

namespace format = checkpoint_format;
using h5::CollectiveSteps;
using h5::Layout;
using h5::Rows;

/// What is written once for all ranks: rank 0's.
struct Shared {
  std::string stage;
  std::map<std::string, std::string> identity;
  std::array<int, 3> channelState{};
  SolveHistory history;
  RefinementHistory refinement;
};

Shared sharedPart(MPI_Comm comm, const Checkpoint& local) {
  Shared shared{local.stage, local.identity, local.progress.channelState, local.progress.history,
                local.refinement};
  h5::broadcast(comm, shared.stage);
  h5::broadcast(comm, shared.identity);
  MPI_Bcast(shared.channelState.data(), 3, MPI_INT, 0, comm);
  h5::broadcast(comm, shared.history);
  h5::broadcast(comm, shared.refinement.roundStart);
  h5::broadcast(comm, shared.refinement.marked);
  h5::broadcast(comm, shared.refinement.patchesAfter);
  h5::broadcast(comm, shared.refinement.mergedStart);
  h5::broadcast(comm, shared.refinement.merged);
  return shared;
}

/// F's one store as the rows of a checkpoint: its rows with its samples, the rows past them (a
/// store filled so far, inside the form-factor stage) with none, every column a patch.
template <class Fail>
void checkStore(const SplitRows& values, const std::vector<int64_t>& rowSamples, int64_t np,
                Fail&& fail) {
  if (values.samples <= 0 || values.samples >= format::kSampleLimit)
    fail("F's store holds " + std::to_string(values.samples) + " samples a row, not 1 to 2^32 - 1");
  if (values.rowCount() > static_cast<int64_t>(rowSamples.size()))
    fail("F's store holds " + std::to_string(values.rowCount()) + " rows, more than the " +
         std::to_string(rowSamples.size()) + " of the checkpoint");
  for (size_t r = 0; r < rowSamples.size(); ++r)
    if (const int64_t held = static_cast<int64_t>(r) < values.rowCount() ? values.samples : 0;
        rowSamples[r] != held)
      fail("row " + std::to_string(values.firstRow + static_cast<int64_t>(r)) +
           " of F's store has " + std::to_string(rowSamples[r]) + " samples, not " +
           std::to_string(held));
  const auto offDiagonal = static_cast<int64_t>(values.offDiagonalBlock.column.size());
  for (int64_t k = 0; k < offDiagonal; ++k)
    if (const int64_t j = values.offDiagonalColumn(k); j < 0 || j >= np)
      fail("F's store has column " + std::to_string(j) + " of " + std::to_string(np));
}

/// Checks what the ranks hold before anything is created, so that bad arguments fail on all ranks
/// together: the row blocks must tile [0, patchCount) in rank order, every rank's rows must be a
/// consistent CSR tally with a number of samples per row (0 to 2^32 - 1; rows with none empty),
/// and the shared part must be storable.
/// Collective.
void checkArguments(CollectiveSteps& steps, MPI_Comm comm, const Checkpoint& local,
                    const Shared& shared) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const SampleTally& rows = local.rows.tally;
  const SplitRows& values = local.rows.values;
  const bool stored = values.rowCount() > 0;  // F's one store: its tally is rebuilt as written
  const int64_t np = local.patchCount;
  int64_t mine[3] = {stored ? values.firstRow : rows.firstRow,
                     stored ? static_cast<int64_t>(local.rows.rowSamples.size()) : rows.rowCount(),
                     np};
  std::vector<int64_t> all(3 * static_cast<size_t>(size));
  MPI_Allgather(mine, 3, MPI_INT64_T, all.data(), 3, MPI_INT64_T, comm);

  steps.run([&] {
    auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
    if (np < 0) fail("the checkpoint has " + std::to_string(np) + " patches");
    const auto sameCount = [&](int r, const int64_t* theirs) {
      if (theirs[2] != np)
        fail("rank " + std::to_string(r) + " has a checkpoint of " + std::to_string(theirs[2]) +
             " patches, others one of " + std::to_string(np));
    };
    checkRankBlocksTile(all, 3, np, {"holds rows", "hold", "rows"}, sameCount);
    const int64_t count = mine[1];
    if (static_cast<int64_t>(local.rows.rowSamples.size()) != count)
      fail("rowSamples has " + std::to_string(local.rows.rowSamples.size()) + " counts for " +
           std::to_string(count) + " rows");
    if (!local.progress.radiosity.empty() &&
        static_cast<int64_t>(local.progress.radiosity.size()) != count)
      fail("radiosity has " + std::to_string(local.progress.radiosity.size()) + " rows, expected " +
           std::to_string(count));
    if (stored) {
      checkStore(values, local.rows.rowSamples, np, fail);
    } else if (rows.rowStart.empty() || rows.rowStart.front() != 0 ||
               rows.rowStart.back() != static_cast<int64_t>(rows.column.size()) ||
               rows.sum.size() != rows.column.size() ||
               !std::is_sorted(rows.rowStart.begin(), rows.rowStart.end()))
      fail("the tally is not in CSR form: row starts from " +
           std::to_string(rows.rowStart.empty() ? -1 : rows.rowStart.front()) + " to " +
           std::to_string(rows.rowStart.empty() ? -1 : rows.rowStart.back()) + " for " +
           std::to_string(rows.column.size()) + " columns and " + std::to_string(rows.sum.size()) +
           " sums");
    for (int64_t r = 0; r < count && !stored; ++r) {
      const int64_t patch = rows.firstRow + r;
      const int64_t samples = local.rows.rowSamples[r];
      if (samples < 0 || samples >= format::kSampleLimit)
        fail("row " + std::to_string(patch) + " has " + std::to_string(samples) +
             " samples, not 0 to 2^32 - 1");
      if (samples == 0 && rows.rowStart[r + 1] != rows.rowStart[r])
        fail("row " + std::to_string(patch) + " has no samples but " +
             std::to_string(rows.rowStart[r + 1] - rows.rowStart[r]) + " entries");
    }
    for (int64_t j : stored ? std::vector<int64_t>() : rows.column)
      if (j < 0 || j >= np)
        fail("the tally has column " + std::to_string(j) + " of " + std::to_string(np));
    // The shared part is the same on every rank, so every rank finds the same problem in it.
    if (std::find(format::kStages.begin(), format::kStages.end(), shared.stage) ==
        format::kStages.end())
      fail("stage \"" + shared.stage + "\" is not formfactors, solve or done");
    for (int c = 0; c < 3; ++c)
      if (shared.channelState[c] < 0 || shared.channelState[c] > 2)
        fail(std::string("the state of channel ") + kChannelNames[c] + " is " +
             std::to_string(shared.channelState[c]) + ", not 0, 1 or 2");
    for (const auto& [key, value] : shared.identity)
      if (key.empty() || key.find('\0') != std::string::npos ||
          value.find('\0') != std::string::npos)
        fail("identity key \"" + key + "\" cannot be stored (empty, or a NUL character)");
    h5::checkHistory(shared.history);
  });
}

/// Seconds from RADIOSITY_TEST_CHECKPOINT_STALL, 0 if unset or not a positive number.
double stallSeconds() {
  const char* text = std::getenv(format::kStallVariable);
  if (text == nullptr) return 0;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  return end != text && seconds > 0 && seconds < 1e6 ? seconds : 0;
}

void writeAttributes(hid_t file, hid_t identity, int64_t np, const Shared& shared) {
  namespace attribute = checkpoint_format::attribute;
  const int version = format::kFormatVersion;
  h5::writeStringAttribute(file, attribute::kKind, format::kKind);
  h5::writeAttribute(file, attribute::kFormatVersion, H5T_STD_I32LE, H5T_NATIVE_INT, &version);
  h5::writeStringAttribute(file, attribute::kStage, shared.stage);
  h5::writeAttribute(file, attribute::kPatchCount, H5T_STD_I64LE, H5T_NATIVE_INT64, &np);
  h5::writeAttribute(file, attribute::kChannelState, H5T_STD_I32LE, H5T_NATIVE_INT,
                     shared.channelState.data(), 3);
  for (const auto& [key, value] : shared.identity)
    h5::writeStringAttribute(identity, key.c_str(), value);
}

/// At most the bytes of the file writeFile writes (io/store/space_reservation.h), the same on
/// every rank. Collective.
int64_t checkpointSpace(MPI_Comm comm, const Checkpoint& local, const Shared& shared,
                        int64_t localNonzeros) {
  const Layout chunks = Layout::kChecksummedChunks;
  const int64_t np = local.patchCount;
  int64_t nonzeros = localNonzeros;
  MPI_Allreduce(MPI_IN_PLACE, &nonzeros, 1, MPI_INT64_T, MPI_SUM, comm);
  h5::SpaceEstimate space;
  space.dataset(np, 0, 8, chunks);
  space.dataset(np + 1, 0, 8, chunks);
  space.dataset(nonzeros, 0, 8, chunks);
  space.dataset(nonzeros, 0, 8, chunks);
  space.dataset(np, 3, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.history.size()), 4, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.refinement.marked.size()), 0, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.refinement.roundStart.size()), 0, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.refinement.patchesAfter.size()), 0, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.refinement.merged.size()), 0, 8, chunks);
  space.dataset(static_cast<int64_t>(shared.refinement.mergedStart.size()), 0, 8, chunks);
  const auto vertices = static_cast<int64_t>(local.mesh.vertices.size()),
             patches = static_cast<int64_t>(local.mesh.triangles.size());
  if (patches > 0) {
    space.dataset(vertices, 3, 8, chunks);
    space.dataset(patches, 3, 8, chunks);
    space.dataset(patches, 0, 8, chunks);
    space.text(local.mesh.input.size());
  }
  space.text(shared.stage.size() + 64, 8);
  for (const auto& [key, value] : shared.identity) space.text(key.size() + value.size());
  return space.bytes();
}

/// The refinement rounds, written by rank 0 (every rank holds them alike). Collective.
void writeRefinement(CollectiveSteps& steps, MPI_Comm comm, hid_t f, hid_t x,
                     const RefinementHistory& refinement) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  for (const auto& [name, values] : {std::pair{format::kMarked, &refinement.marked},
                                     std::pair{format::kRoundStart, &refinement.roundStart},
                                     std::pair{format::kPatchesAfter, &refinement.patchesAfter},
                                     std::pair{format::kMerged, &refinement.merged},
                                     std::pair{format::kMergedStart, &refinement.mergedStart},
                                     std::pair{format::kRoundRays, &refinement.raysAfter}}) {
    const auto count = static_cast<int64_t>(values->size());
    h5::writeDataset(steps, f, x,
                     {name, H5T_STD_I64LE, H5T_NATIVE_INT64, count, 0, Layout::kChecksummedChunks},
                     Rows{0, rank == 0 ? count : 0}, values->data());
  }
  const auto rounds = static_cast<int64_t>(refinement.estimateBefore.size());
  h5::writeDataset(steps, f, x,
                   {format::kRoundEstimate, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rounds, 0,
                    Layout::kChecksummedChunks},
                   Rows{0, rank == 0 ? rounds : 0}, refinement.estimateBefore.data());
}

/// The mesh, written by rank 0 (every rank holds it alike; rank 0's sizes for all). Collective.
void writeMesh(CollectiveSteps& steps, MPI_Comm comm, hid_t f, hid_t x,
               const CheckpointMeshView& mesh) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::array<int64_t, 2> size{static_cast<int64_t>(mesh.vertices.size()),
                              static_cast<int64_t>(mesh.triangles.size())};
  MPI_Bcast(size.data(), 2, MPI_INT64_T, 0, comm);
  const auto [vertices, patches] = size;
  const Rows all{0, rank == 0 ? vertices : 0}, allPatches{0, rank == 0 ? patches : 0};
  // (from the run's arrays in place: flattened copies were rank 0's peak at the end of a run)
  h5::writeDataset(steps, f, x,
                   {format::kMeshVertices, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, vertices, 3,
                    Layout::kChecksummedChunks},
                   all, h5::rowsInPlace<double>(mesh.vertices, all));
  h5::writeDataset(steps, f, x,
                   {format::kMeshTriangles, H5T_STD_I64LE, H5T_NATIVE_INT64, patches, 3,
                    Layout::kChecksummedChunks},
                   allPatches, h5::rowsInPlace<int64_t>(mesh.triangles, allPatches));
  h5::writeDataset(steps, f, x,
                   {format::kMeshSourceFace, H5T_STD_I64LE, H5T_NATIVE_INT64, patches, 0,
                    Layout::kChecksummedChunks},
                   allPatches, mesh.sourceFace.data());
}

/// Where this rank's rows of the tally go: their first row and their starts (rowStart[0] = 0).
struct TallyLayout {
  int64_t firstRow = 0;
  std::vector<int64_t> rowStart;
};

/// Rows of the store rebuilt as tally about this many nonzeros at a time (32 MB of tally, and as
/// much again in HDF5's chunk buffers), so that neither is ever large beside F.
constexpr int64_t kNonzerosPerPiece = int64_t{1} << 19;

/// Rows [from, to) of this rank's tally: from F's one store, rebuilt (its rows past those it
/// holds, inside the form-factor stage, empty), or from the tally itself.
SampleTally tallyPiece(const SampledRows& rows, int64_t from, int64_t to) {
  const SplitRows& values = rows.values;
  if (values.rowCount() == 0) return rows.tally.slice(from, to, rows.tally.samples);
  const int64_t end = std::min(to, values.rowCount());
  return values.tally(std::min(from, end), end);
}

/// The column and sum datasets, this rank's rows (tallyPiece) about kNonzerosPerPiece at a time,
/// the same number of pieces on every rank (the writes are collective), whichever form each
/// rank holds its rows in.
void writeTally(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                const SampledRows& rows, const std::vector<int64_t>& rowStart,
                h5::Offsets offsets) {
  h5::Handle column, sum;
  const auto chunks = Layout::kChecksummedChunks;
  steps.run([&] {
    column = h5::createVectorDataset(file, format::kColumn, H5T_STD_I64LE, offsets.total, chunks);
    sum = h5::createVectorDataset(file, format::kSum, H5T_STD_I64LE, offsets.total, chunks);
  });
  h5::writePieces(steps, comm, rowStart, offsets.total, kNonzerosPerPiece,
                  [&](int64_t from, int64_t to) {
                    const SampleTally piece = tallyPiece(rows, from, to);
                    const int64_t first = offsets.before + rowStart[from];
                    const auto count = static_cast<int64_t>(piece.column.size());
                    h5::writeSlab(column.get(), format::kColumn, transfer, H5T_NATIVE_INT64, first,
                                  count, piece.column.data());
                    h5::writeSlab(sum.get(), format::kSum, transfer, H5T_NATIVE_INT64, first, count,
                                  piece.sum.data());
                  });
  steps.run([&] {
    column.close("H5Dclose(/formfactors/column)");
    sum.close("H5Dclose(/formfactors/sum)");
  });
}

/// Creates `temporary` and writes everything into it; all HDF5 handles are closed on return, on
/// success and failure alike. Collective.
void writeFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& temporary,
               const Checkpoint& local, const Shared& shared, const TallyLayout& tally,
               int64_t reserveBytes) {
  const int64_t np = local.patchCount;
  const Rows mine{tally.firstRow, static_cast<int64_t>(tally.rowStart.size()) - 1};
  const Layout chunks = Layout::kChecksummedChunks;

  h5::ParallelFile parallel =
      h5::createParallelFile(steps, comm, temporary, /*checksummedMetadata=*/true, reserveBytes);
  h5::Handle identityGroup, formFactorGroup, solveGroup, refinementGroup, meshGroup;
  const bool withMesh = !local.mesh.empty();  // (alike on every rank)
  steps.run([&] {
    identityGroup = h5::createGroup(parallel.file.get(), format::kIdentity);
    formFactorGroup = h5::createGroup(parallel.file.get(), format::kFormFactors);
    solveGroup = h5::createGroup(parallel.file.get(), format::kSolve);
    refinementGroup = h5::createGroup(parallel.file.get(), format::kRefinement);
    if (withMesh) meshGroup = h5::createGroup(parallel.file.get(), format::kMesh);
  });

  const hid_t f = parallel.file.get(), x = parallel.transfer.get();
  h5::writeDataset(steps, f, x, {format::kSamples, H5T_STD_I64LE, H5T_NATIVE_INT64, np, 0, chunks},
                   mine, local.rows.rowSamples.data());
  const int64_t nonzeros = tally.rowStart.back();
  const auto [before, total] = h5::offsetsInRankOrder(comm, nonzeros);
  if (steps.ok()) {
    // Row starts become global offsets; the last rank also writes the end, row_start[np].
    const std::vector<int64_t> rowStart = h5::globalRowStarts(comm, tally.rowStart, before);
    h5::writeDataset(steps, f, x,
                     {format::kRowStart, H5T_STD_I64LE, H5T_NATIVE_INT64, np + 1, 0, chunks},
                     Rows{tally.firstRow, static_cast<int64_t>(rowStart.size())}, rowStart.data());
  }
  writeTally(steps, comm, f, x, local.rows, tally.rowStart, {before, total});
  if (steps.ok()) {
    std::vector<double> balance(static_cast<size_t>(mine.count), 1.0);
    if (local.rowBalance.size() == balance.size()) balance = local.rowBalance;
    h5::writeDataset(steps, f, x,
                     {format::kRowBalance, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 0, chunks}, mine,
                     balance.data());
  }
  if (steps.ok()) {
    // B in place once every row has it (the final checkpoint, at the run's memory peak); zeros
    // for the rows not solved yet.
    const std::span<const Rgb> b(local.progress.radiosity);
    const bool whole = static_cast<int64_t>(b.size()) == mine.count;
    const std::vector<double> flat =
        whole ? std::vector<double>() : h5::flattenRows(b, {0, mine.count});
    h5::writeDataset(steps, f, x,
                     {format::kRadiosity, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, np, 3, chunks}, mine,
                     whole ? h5::rowsInPlace<double>(b, {0, mine.count}) : flat.data());
  }
  h5::writeSolveHistory(steps, comm, f, x, format::kHistory, shared.history, chunks);
  writeRefinement(steps, comm, f, x, shared.refinement);
  if (withMesh) writeMesh(steps, comm, f, x, local.mesh);
  steps.run([&] {
    writeAttributes(f, identityGroup.get(), np, shared);
    if (withMesh)
      h5::writeStringAttribute(meshGroup.get(), format::kMeshInput, std::string(local.mesh.input));
  });

  if (steps.ok()) {
    if (const double seconds = stallSeconds(); seconds > 0)
      std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
  steps.run([&] {
    if (withMesh) meshGroup.close("H5Gclose(/mesh)");
    refinementGroup.close("H5Gclose(/refinement)");
    solveGroup.close("H5Gclose(/solve)");
    formFactorGroup.close("H5Gclose(/formfactors)");
    identityGroup.close("H5Gclose(/identity)");
    // The data on disk (MPI_File_sync on every rank) before the rename makes them the checkpoint.
    h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "H5Fflush(" + temporary + ")");
    // Closing is where the remaining metadata reach the disk, so its failure counts.
    parallel.file.close("H5Fclose(" + temporary + ")");
  });
  h5::releaseUnusedSpace(steps, comm, temporary);
}

}  // namespace

void stageCheckpoint(CollectiveOutputs& outputs, const std::string& path, const Checkpoint& local) {
  const MPI_Comm comm = outputs.comm();
  h5::QuietErrors quiet;
  CollectiveSteps steps(comm);
  const Shared shared = sharedPart(comm, local);
  checkArguments(steps, comm, local, shared);
  if (!steps.ok())
    throw Error(exit_code::kFailure, "cannot write checkpoint " + path + ": " + steps.error());
  const SplitRows& values = local.rows.values;
  TallyLayout tally = values.rowCount() > 0
                          ? TallyLayout{values.firstRow, values.tallyRowStart()}
                          : TallyLayout{local.rows.tally.firstRow, local.rows.tally.rowStart};
  if (values.rowCount() > 0)  // the rows past a store filled so far: empty
    tally.rowStart.resize(local.rows.rowSamples.size() + 1, tally.rowStart.back());
  const int64_t reserveBytes = checkpointSpace(comm, local, shared, tally.rowStart.back());
  const std::string temporary = outputs.stage(path, /*durable=*/true);
  writeFile(steps, comm, temporary, local, shared, tally, reserveBytes);
  if (!steps.ok()) {
    outputs.unstage(path);
    throw Error(exit_code::kFailure, "cannot write checkpoint " + path + ": " + steps.error());
  }
}

void writeCheckpoint(MPI_Comm comm, const std::string& path, const Checkpoint& local) {
  CollectiveOutputs outputs(comm);
  stageCheckpoint(outputs, path, local);
  outputs.commit();
}

}  // namespace radiosity
