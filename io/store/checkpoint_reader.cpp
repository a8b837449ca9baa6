// Reads the checkpoint written by checkpoint_writer.cpp (layout in io/store/checkpoint_format.h);
// `radiosity info`'s description of one (checkpoint_description.cpp) reads through the same
// checks (checkpoint_reading.h).
//
// readCheckpoint: every rank opens the file read-only with serial HDF5 and reads its own rows,
// whatever the decomposition that wrote them, plus the small shared part whole; then the ranks
// agree (runCollectively). No HDF5 call is collective, so a rank that meets a damaged chunk cannot
// leave the others waiting; every rank then throws the InputError of the lowest failing rank.
// HDF5 verifies the Fletcher32 checksum of every chunk it reads (and of the metadata), and the
// reader checks what a checksum cannot: shapes, that row_start runs from 0 to nnz without going
// down, columns in range, samples per row from 0 to 2^32 - 1, rows without samples empty,
// states and stage known. Files of format version 1 (a finished flag per row) are refused.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/error.h"
#include "core/input_file.h"
#include "io/store/checkpoint.h"
#include "io/store/checkpoint_format.h"
#include "io/store/checkpoint_reading.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "parallel/collective.h"

namespace radiosity {
namespace {

namespace format = checkpoint_format;

const std::string kCorrupted = "corrupted checkpoint: ";

[[noreturn]] void corrupted(const std::string& path, const std::string& problem) {
  h5::fail(path, kCorrupted + problem);
}

/// Runs `read`, a part of reading `path` that a checkpoint must pass; whatever it finds wrong
/// becomes an InputError saying the checkpoint is corrupted, naming `what` (a dataset, or the
/// attributes) when HDF5 failed.
template <class Read>
auto guarded(const std::string& path, const std::string& what, Read&& read) {
  try {
    return read();
  } catch (const h5::Failure& e) {
    const std::string text = e.what();
    if (text.find("checksum") != std::string::npos)
      corrupted(path, "checksum mismatch in " + what + " (" + text + ")");
    corrupted(path, "cannot read " + what + " (" + text + ")");
  } catch (const InputError& e) {
    // The shared readers' "path: problem", said to be about a corrupted checkpoint.
    const std::string message = e.what(), prefix = path + ": ";
    if (message.rfind(prefix, 0) != 0 || message.find(kCorrupted) == prefix.size()) throw;
    corrupted(path, message.substr(prefix.size()));
  }
}

}  // namespace

h5::Handle openCheckpoint(const std::string& path) {
  requireRegularFile(path, "checkpoint");  // H5Fis_hdf5 opens it: a FIFO would block there
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
  if (isHdf5 < 0) h5::fail(path, "cannot read: " + h5::takeErrorText());
  if (isHdf5 == 0) h5::fail(path, "not a checkpoint (not an HDF5 file)");
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  // A file whose first bytes are HDF5's but which does not open is a damaged one: most often
  // truncated (HDF5 says so).
  if (id < 0) corrupted(path, "cannot open (" + h5::takeErrorText() + ")");
  h5::Handle file(id);
  h5::requireSelfContained(id, path);
  const std::string kind =
      guarded(path, "the root attributes", [&] { return h5::kindAttribute(id); });
  if (kind != format::kKind)
    h5::fail(path, kind.empty() ? std::string("not a checkpoint (an HDF5 file without kind = \"") +
                                      format::kKind + "\")"
                                : "not a checkpoint (kind = \"" + kind + "\")");
  return file;
}

namespace {

/// The refinement rounds (none when the file has no /refinement), checked to be rounds of marks:
/// round starts from 0 to the marks' count without going down, marks not negative, a patch
/// count per round (that the marks are patches of the mesh each round starts from, and that the
/// round gives its count, is checked as they are replayed).
RefinementHistory readRefinement(hid_t file, const std::string& path) {
  RefinementHistory refinement;
  if (!h5::exists(file, format::kRefinement)) return refinement;
  int64_t marks = -1, starts = -1, rounds = -1;
  refinement.marked = guarded(path, format::kMarked, [&] {
    return h5::readDataset<int64_t>(file, path, format::kMarked, H5T_NATIVE_INT64, 0, marks);
  });
  refinement.roundStart = guarded(path, format::kRoundStart, [&] {
    return h5::readDataset<int64_t>(file, path, format::kRoundStart, H5T_NATIVE_INT64, 0, starts);
  });
  refinement.patchesAfter = guarded(path, format::kPatchesAfter, [&] {
    return h5::readDataset<int64_t>(file, path, format::kPatchesAfter, H5T_NATIVE_INT64, 0, rounds);
  });
  const std::vector<int64_t>& start = refinement.roundStart;
  if (rounds + 1 != starts)
    corrupted(path, std::string(format::kPatchesAfter) + " has " + std::to_string(rounds) +
                        " rounds, " + format::kRoundStart + " " + std::to_string(starts - 1));
  if (start.empty() || start.front() != 0 || start.back() != marks ||
      !std::is_sorted(start.begin(), start.end()))
    corrupted(path, std::string(format::kRoundStart) + " does not run from 0 to " +
                        std::to_string(marks) + " (the marks in " + format::kMarked + ")");
  for (int64_t t : refinement.marked)
    if (t < 0) corrupted(path, std::string(format::kMarked) + " holds " + std::to_string(t));
  // The bisections undone (none in a checkpoint of a version that undid none).
  refinement.mergedStart.assign(start.size(), 0);
  if (h5::exists(file, format::kMergedStart)) {
    int64_t merged = -1, mergedStarts = -1;
    refinement.merged = guarded(path, format::kMerged, [&] {
      return h5::readDataset<int64_t>(file, path, format::kMerged, H5T_NATIVE_INT64, 0, merged);
    });
    refinement.mergedStart = guarded(path, format::kMergedStart, [&] {
      return h5::readDataset<int64_t>(file, path, format::kMergedStart, H5T_NATIVE_INT64, 0,
                                      mergedStarts);
    });
    const std::vector<int64_t>& m = refinement.mergedStart;
    if (mergedStarts != starts || m.front() != 0 || m.back() != merged ||
        !std::is_sorted(m.begin(), m.end()))
      corrupted(path, std::string(format::kMergedStart) + " does not run from 0 to " +
                          std::to_string(merged) + " over " + std::to_string(starts - 1) +
                          " rounds (the vertices in " + format::kMerged + ")");
    for (int64_t v : refinement.merged)
      if (v < 0) corrupted(path, std::string(format::kMerged) + " holds " + std::to_string(v));
  }
  // Each round's rays and the estimate it was taken on (none in a checkpoint of a version
  // that did not record them: a restart then goes on at --rays).
  refinement.raysAfter.assign(start.size() - 1, 0);
  refinement.estimateBefore.assign(start.size() - 1, 0);
  if (h5::exists(file, format::kRoundRays)) {
    int64_t count = rounds;
    refinement.raysAfter = guarded(path, format::kRoundRays, [&] {
      return h5::readDataset<int64_t>(file, path, format::kRoundRays, H5T_NATIVE_INT64, 0, count);
    });
    refinement.estimateBefore = guarded(path, format::kRoundEstimate, [&] {
      return h5::readDataset<double>(file, path, format::kRoundEstimate, H5T_NATIVE_DOUBLE, 0,
                                     count);
    });
    for (int64_t r : refinement.raysAfter)
      if (r < 0 || r > (int64_t{1} << 32))
        corrupted(path, std::string(format::kRoundRays) + " holds " + std::to_string(r));
    for (double e : refinement.estimateBefore)
      if (!(e >= 0) || !std::isfinite(e))
        corrupted(path, std::string(format::kRoundEstimate) + " holds " + std::to_string(e));
  }
  return refinement;
}

}  // namespace

Checkpoint readCheckpointShared(hid_t file, const std::string& path) {
  Checkpoint c;
  const int64_t version = guarded(path, "the attributes", [&] {
    return h5::readAttribute<int64_t>(file, path, format::attribute::kFormatVersion);
  });
  // Not damage: a checkpoint of an older or newer program.
  if (version != format::kFormatVersion)
    h5::fail(path, "unsupported checkpoint format version " + std::to_string(version) +
                       " (this program reads version " + std::to_string(format::kFormatVersion) +
                       ")");
  guarded(path, "the attributes", [&] {
    c.stage = h5::readAttribute<std::string>(file, path, format::attribute::kStage);
    if (std::find(format::kStages.begin(), format::kStages.end(), c.stage) == format::kStages.end())
      corrupted(path, "stage \"" + c.stage + "\" is not formfactors, solve or done");
    c.patchCount = h5::readAttribute<int64_t>(file, path, format::attribute::kPatchCount);
    if (c.patchCount < 0)
      corrupted(path, "patch_count is " + std::to_string(c.patchCount) + ", negative");
    const std::vector<int64_t> states =
        h5::readNumbers<int64_t>(file, path, format::attribute::kChannelState, 3);
    for (int k = 0; k < 3; ++k) {
      if (states[k] < 0 || states[k] > 2)
        corrupted(path, std::string("channel_state of ") + kChannelNames[k] + " is " +
                            std::to_string(states[k]) + ", not 0, 1 or 2");
      c.progress.channelState[k] = static_cast<int>(states[k]);
    }
  });
  guarded(path, format::kIdentity, [&] {
    if (!h5::exists(file, format::kIdentity))
      h5::fail(path, std::string("missing group ") + format::kIdentity);
    h5::Handle group = h5::own(H5Gopen2(file, format::kIdentity, H5P_DEFAULT), "H5Gopen2");
    for (const std::string& key : h5::attributeNames(group.get()))
      c.identity[key] = h5::readAttribute<std::string>(group.get(), path, key);
  });
  c.progress.history = guarded(path, format::kHistory,
                               [&] { return h5::readSolveHistory(file, path, format::kHistory); });
  c.refinement = readRefinement(file, path);
  return c;
}

namespace {

/// Checks the samples of row `row` (corruption if negative or not below 2^32).
void checkSamples(const std::string& path, int64_t row, int64_t samples) {
  if (samples < 0 || samples >= format::kSampleLimit)
    corrupted(path, std::string(format::kSamples) + " holds " + std::to_string(samples) +
                        " for row " + std::to_string(row) + ", not 0 to 2^32 - 1");
}

}  // namespace

std::vector<int64_t> readCheckpointSamples(hid_t file, const std::string& path, int64_t rows) {
  const std::vector<int64_t> samples = guarded(path, format::kSamples, [&] {
    return h5::readDataset<int64_t>(file, path, format::kSamples, H5T_NATIVE_INT64, 0, rows);
  });
  for (int64_t r = 0; r < rows; ++r) checkSamples(path, r, samples[r]);
  return samples;
}

namespace {

/// This rank's part: rows [firstRow, endRow) and the shared part. Throws InputError.
Checkpoint readPart(const std::string& path, int64_t firstRow, int64_t endRow) {
  if (firstRow < 0 || endRow < firstRow)
    throw std::invalid_argument("readCheckpoint: rows [" + std::to_string(firstRow) + ", " +
                                std::to_string(endRow) + ") are no range of rows");
  h5::QuietErrors quiet;
  h5::Handle file = openCheckpoint(path);
  const hid_t f = file.get();
  Checkpoint c = readCheckpointShared(f, path);
  const int64_t np = c.patchCount;
  if (endRow > np)
    h5::fail(path, "the checkpoint has " + std::to_string(np) + " patches, not rows " +
                       std::to_string(firstRow) + " to " + std::to_string(endRow) +
                       " (it belongs to another scene or meshing)");
  const int64_t count = endRow - firstRow;
  c.rows.tally.firstRow = firstRow;

  int64_t total = np;
  c.rows.rowSamples = guarded(path, format::kSamples, [&] {
    return h5::readDataset<int64_t>(f, path, format::kSamples, H5T_NATIVE_INT64, 0, total,
                                    h5::Rows{firstRow, count});
  });
  for (int64_t r = 0; r < count; ++r) checkSamples(path, firstRow + r, c.rows.rowSamples[r]);
  // Not used (rows differ); the largest of this rank's, for whoever looks.
  c.rows.tally.samples = c.rows.rowSamples.empty() ? 0
                                                   : *std::max_element(c.rows.rowSamples.begin(),
                                                                       c.rows.rowSamples.end());

  int64_t starts = np + 1;
  const std::vector<int64_t> rowStart = guarded(path, format::kRowStart, [&] {
    return h5::readDataset<int64_t>(f, path, format::kRowStart, H5T_NATIVE_INT64, 0, starts,
                                    h5::Rows{firstRow, count + 1});
  });
  // The number of nonzeros, from the shape of column (whose chunks this reads none of).
  int64_t nonzeros = -1;
  guarded(path, format::kColumn, [&] {
    return h5::readDataset<int64_t>(f, path, format::kColumn, H5T_NATIVE_INT64, 0, nonzeros,
                                    h5::Rows{0, 0});
  });
  const std::string where = std::string(format::kRowStart) + " ";
  if (firstRow == 0 && rowStart.front() != 0)
    corrupted(path, where + "starts at " + std::to_string(rowStart.front()) + ", not 0");
  if (endRow == np && rowStart.back() != nonzeros)
    corrupted(path, where + "ends at " + std::to_string(rowStart.back()) + ", not at " +
                        std::to_string(nonzeros) + " (the length of " + format::kColumn + ")");
  for (int64_t r = 0; r <= count; ++r) {
    if (rowStart[r] < 0 || rowStart[r] > nonzeros)
      corrupted(path, where + "holds " + std::to_string(rowStart[r]) + " at " +
                          std::to_string(firstRow + r) + ", outside 0 to " +
                          std::to_string(nonzeros));
    if (r > 0 && rowStart[r] < rowStart[r - 1])
      corrupted(path, where + "goes down from " + std::to_string(rowStart[r - 1]) + " to " +
                          std::to_string(rowStart[r]) + " at row " + std::to_string(firstRow + r));
    if (r > 0 && c.rows.rowSamples[r - 1] == 0 && rowStart[r] != rowStart[r - 1])
      corrupted(path, "row " + std::to_string(firstRow + r - 1) + " has no samples (" +
                          format::kSamples + ") but " +
                          std::to_string(rowStart[r] - rowStart[r - 1]) + " entries");
  }
  const int64_t first = rowStart.front(), entries = rowStart.back() - rowStart.front();
  c.rows.tally.rowStart.resize(count + 1);
  for (int64_t r = 0; r <= count; ++r) c.rows.tally.rowStart[r] = rowStart[r] - first;
  c.rows.tally.column = guarded(path, format::kColumn, [&] {
    return h5::readDataset<int64_t>(f, path, format::kColumn, H5T_NATIVE_INT64, 0, nonzeros,
                                    h5::Rows{first, entries});
  });
  for (int64_t j : c.rows.tally.column)
    if (j < 0 || j >= np)
      corrupted(path, std::string(format::kColumn) + " holds " + std::to_string(j) +
                          ", not a patch of " + std::to_string(np));
  c.rows.tally.sum = guarded(path, format::kSum, [&] {
    return h5::readDataset<int64_t>(f, path, format::kSum, H5T_NATIVE_INT64, 0, nonzeros,
                                    h5::Rows{first, entries});
  });

  int64_t patches = np;
  const std::vector<double> radiosity = guarded(path, format::kRadiosity, [&] {
    return h5::readDataset<double>(f, path, format::kRadiosity, H5T_NATIVE_DOUBLE, 3, patches,
                                   h5::Rows{firstRow, count});
  });
  c.progress.radiosity.resize(count);
  for (int64_t r = 0; r < count; ++r)
    for (int k = 0; k < 3; ++k) c.progress.radiosity[r][k] = radiosity[3 * r + k];
  if (h5::exists(f, format::kRowBalance)) {  // (files of earlier versions have none)
    int64_t rows = np;
    c.rowBalance = guarded(path, format::kRowBalance, [&] {
      return h5::readDataset<double>(f, path, format::kRowBalance, H5T_NATIVE_DOUBLE, 0, rows,
                                     h5::Rows{firstRow, count});
    });
  }
  return c;
}

/// Runs read(file) on every rank with `path` open as a checkpoint, the ranks agreeing
/// (runCollectively); a problem of the file's (exit code 3) is an InputError on every rank.
template <class Read>
void readOnEveryRank(MPI_Comm comm, const std::string& path, Read&& read) {
  try {
    runCollectively(comm, [&] {
      h5::QuietErrors quiet;
      h5::Handle file = openCheckpoint(path);
      read(file.get());
    });
  } catch (const Error& e) {
    if (e.exitCode() == exit_code::kBadInput) throw InputError(e.what());
    throw;
  }
}

/// The mesh (none where the file has no /mesh), checked as readCheckpointMesh says.
CheckpointMesh readMesh(hid_t f, const std::string& path) {
  CheckpointMesh mesh;
  readCheckpointShared(f, path);  // (the version and the attributes checked as for the rows)
  if (!h5::exists(f, format::kMesh)) return mesh;
  mesh.input = guarded(path, format::kMesh, [&] {
    h5::Handle group = h5::own(H5Gopen2(f, format::kMesh, H5P_DEFAULT), "H5Gopen2");
    return h5::readAttribute<std::string>(group.get(), path, format::kMeshInput);
  });
  int64_t vertices = -1, patches = -1, faces = -1;
  const std::vector<double> corners = guarded(path, format::kMeshVertices, [&] {
    return h5::readDataset<double>(f, path, format::kMeshVertices, H5T_NATIVE_DOUBLE, 3, vertices);
  });
  const std::vector<int64_t> triangles = guarded(path, format::kMeshTriangles, [&] {
    return h5::readDataset<int64_t>(f, path, format::kMeshTriangles, H5T_NATIVE_INT64, 3, patches);
  });
  mesh.sourceFace = guarded(path, format::kMeshSourceFace, [&] {
    return h5::readDataset<int64_t>(f, path, format::kMeshSourceFace, H5T_NATIVE_INT64, 0, faces);
  });
  if (faces != patches)
    corrupted(path, std::string(format::kMeshSourceFace) + " has " + std::to_string(faces) +
                        " patches, " + format::kMeshTriangles + " " + std::to_string(patches));
  mesh.vertices.resize(static_cast<size_t>(vertices));
  for (int64_t v = 0; v < vertices; ++v) {
    mesh.vertices[v] = {corners[3 * v], corners[3 * v + 1], corners[3 * v + 2]};
    if (!std::isfinite(corners[3 * v]) || !std::isfinite(corners[3 * v + 1]) ||
        !std::isfinite(corners[3 * v + 2]))
      corrupted(path, std::string(format::kMeshVertices) + " row " + std::to_string(v) +
                          " is not finite");
  }
  mesh.triangles.resize(static_cast<size_t>(patches));
  for (int64_t t = 0; t < patches; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int64_t corner = triangles[3 * t + k];
      if (corner < 0 || corner >= vertices)
        corrupted(path, std::string(format::kMeshTriangles) + " row " + std::to_string(t) +
                            " names vertex " + std::to_string(corner) + " of " +
                            std::to_string(vertices));
      mesh.triangles[t][k] = corner;
    }
    if (mesh.sourceFace[t] < 0)
      corrupted(path, std::string(format::kMeshSourceFace) + " holds " +
                          std::to_string(mesh.sourceFace[t]));
  }
  return mesh;
}

}  // namespace

Checkpoint readCheckpoint(MPI_Comm comm, const std::string& path, int64_t firstRow,
                          int64_t endRow) {
  Checkpoint checkpoint;
  try {
    runCollectively(comm, [&] { checkpoint = readPart(path, firstRow, endRow); });
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    // runCollectively keeps the exit code but not the type, which callers may catch by.
    if (e.exitCode() == exit_code::kBadInput) throw InputError(e.what());
    throw;
  }
  return checkpoint;
}

RefinementHistory readCheckpointRefinement(MPI_Comm comm, const std::string& path) {
  RefinementHistory refinement;
  readOnEveryRank(comm, path,
                  [&](hid_t file) { refinement = readCheckpointShared(file, path).refinement; });
  return refinement;
}

std::map<std::string, std::string> readCheckpointIdentity(MPI_Comm comm, const std::string& path) {
  std::map<std::string, std::string> identity;
  readOnEveryRank(comm, path,
                  [&](hid_t file) { identity = readCheckpointShared(file, path).identity; });
  return identity;
}

CheckpointMesh readCheckpointMesh(MPI_Comm comm, const std::string& path) {
  CheckpointMesh mesh;
  readOnEveryRank(comm, path, [&](hid_t file) { mesh = readMesh(file, path); });
  return mesh;
}

}  // namespace radiosity
