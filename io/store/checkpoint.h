// The checkpoint of an interrupted solve (HDF5): written collectively and durably, read back
// under any decomposition.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "core/run_state.h"
#include "io/store/collective_outputs.h"

namespace radiosity {

/// The patches F's rows are over, as the run meshed them (in the scene's coordinates), and the
/// fingerprint of the scene and the meshing options they were made from (`input`): a run that
/// reuses F (--formfactors-from) takes them instead of meshing again, which F then belongs to
/// whatever a later version's meshing would make. Empty: none (files of earlier versions).
struct CheckpointMesh {
  std::string input;
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  std::vector<int64_t> sourceFace;  ///< the scene's face each patch came from
  bool empty() const { return triangles.empty(); }
};

/// The same as the writer takes it: views of the caller's arrays, which must outlive the write.
/// A run holds its patches already; a copy for its checkpoints was 44 MB a rank at 10^6 patches.
struct CheckpointMeshView {
  std::string_view input;
  std::span<const Vec3> vertices;
  std::span<const Triangle> triangles;
  std::span<const int64_t> sourceFace;
  bool empty() const { return triangles.empty(); }
};

inline CheckpointMeshView viewOf(const CheckpointMesh& mesh) {
  return {mesh.input, mesh.vertices, mesh.triangles, mesh.sourceFace};
}

/// The state of an interrupted (or finished) `radiosity solve`: this rank's share of it.
struct Checkpoint {
  std::string stage;  ///< "formfactors", "solve" or "done": the stage running when written
  /// What a restart must match, name → value (the scene's fingerprint, meshing, sampling and
  /// solver options); the same on every rank (rank 0's is written).
  std::map<std::string, std::string> identity;
  int64_t patchCount = 0;
  /// This rank's rows [rows.tally.firstRow, + rows.tally.rowCount()). Read back, rows.tally.samples
  /// is the largest of this rank's rowSamples (0 if none).
  SampledRows rows;
  /// The refinement rounds that made the mesh from the first one (rank 0's when written).
  RefinementHistory refinement;
  /// The solve's progress; its channel states and history are rank 0's when written.
  /// radiosity: this rank's rows, or empty (written as 0) before the solve.
  SolveProgress progress;
  /// This rank's rows: the row factors u_i of a thermal run's balance of F (solve::balanceColumns),
  /// which a run reusing F starts from, so that it needs a sweep or two instead of many; empty:
  /// none (written as 1, read back as empty where the file has none).
  std::vector<double> rowBalance;
  /// Every rank's alike (rank 0's is written); not read back by readCheckpoint (see
  /// readCheckpointMesh).
  CheckpointMeshView mesh;
};

/// Writes a checkpoint collectively, each rank its rows, under the temporary name `outputs`
/// gives it (durable: synced before its rename at outputs.commit(); killing the job mid-write
/// leaves an existing `path` intact). Every dataset is chunked with HDF5's Fletcher32 checksum,
/// so corruption is found when read. Throws Error(kFailure) on an I/O failure.
void stageCheckpoint(CollectiveOutputs& outputs, const std::string& path, const Checkpoint& local);
/// stageCheckpoint() and commit, for a checkpoint written alone (during the run).
void writeCheckpoint(MPI_Comm comm, const std::string& path, const Checkpoint& local);

/// Reads a checkpoint collectively: its rows [firstRow, endRow) (this rank's under the current
/// decomposition, which may differ from the writer's) and the rest whole. A missing, truncated
/// or corrupted file (checksum mismatch, missing or inconsistent dataset) throws InputError
/// naming the file and the problem (exit code 3) on every rank.
Checkpoint readCheckpoint(MPI_Comm comm, const std::string& path, int64_t firstRow, int64_t endRow);

/// The refinement rounds of a checkpoint alone (what a restart replays before it knows its
/// rows). Collective; InputError as readCheckpoint().
RefinementHistory readCheckpointRefinement(MPI_Comm comm, const std::string& path);

/// The identity of a checkpoint's run alone (what a run reusing its F takes the estimator from
/// before it plans). Collective; InputError as readCheckpoint().
std::map<std::string, std::string> readCheckpointIdentity(MPI_Comm comm, const std::string& path);

/// The mesh of a checkpoint alone, whole on every rank (what a run reusing F takes before it
/// reads the rows); empty where the file has none. Checked: triangles' corners among the
/// vertices, finite coordinates, source faces not negative. Collective; InputError as
/// readCheckpoint().
CheckpointMesh readCheckpointMesh(MPI_Comm comm, const std::string& path);

/// True if `path` is an HDF5 file written by writeCheckpoint (serial; any rank).
bool isCheckpoint(const std::string& path);
/// For `radiosity info`: stage, identity, rows sampled of all patches, the distinct numbers of
/// samples per row (with their row counts), channel states, history length. Serial.
std::string describeCheckpoint(const std::string& path);

}  // namespace radiosity
