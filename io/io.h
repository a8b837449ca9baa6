// io: the scene in (OBJ+MTL, built-in scenes) and the result out (HDF5), plus the small geometry
// types every stage shares. HDF5 stays behind this header; MPI appears only as a communicator.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/collective_outputs.h"
#include "io/vec3.h"

namespace radiosity {

/// An error the user can act on; `exitCode` is the one CONTRACT.md gives it.
class Error : public std::runtime_error {
 public:
  Error(int exitCode, const std::string& message)
      : std::runtime_error(message), exitCode_(exitCode) {}
  int exitCode() const { return exitCode_; }

 private:
  int exitCode_;
};

namespace exit_code {
inline constexpr int kOk = 0;
inline constexpr int kFailure = 1;
inline constexpr int kUsage = 2;
inline constexpr int kBadInput = 3;
inline constexpr int kNumerical = 4;
inline constexpr int kStoppedBySignal = 75;
}  // namespace exit_code

/// Bad scene, material or job file. The message starts with "file:line: " where a line is known.
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(exit_code::kBadInput, message) {}
  InputError(const std::string& file, long line, const std::string& problem)
      : Error(exit_code::kBadInput, file + ":" + std::to_string(line) + ": " + problem) {}
};

/// Runs `work` on every rank of `comm` and makes its outcome collective: if it threw on any
/// rank, every rank throws the Error of the lowest such rank (same exit code, same message).
/// Wrap rank-local work in it so that no rank is left waiting in a collective. Collective.
void runCollectively(MPI_Comm comm, const std::function<void()>& work);

using Triangle = std::array<int64_t, 3>;

/// A triangle mesh with one material per triangle. Used both for the scene as loaded (one
/// triangle per input triangle) and for the patches after meshing (one triangle per patch, in
/// global patch id order). Every rank holds the whole mesh.
struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  std::vector<int64_t> sourceFace;  ///< 0-based input face each triangle came from
  std::vector<Rgb> reflectance;     ///< ρ per triangle, each channel in [0, 1]
  std::vector<Rgb> emission;        ///< E per triangle (exitance), each channel ≥ 0
  /// Material and group/object of each triangle, for messages: e.g. 'red_wall (group walls)'.
  /// label[t] indexes labelNames. Optional: an empty `label` means "no labels". Not stored in
  /// the result file.
  std::vector<int32_t> label;
  std::vector<std::string> labelNames;
  std::vector<std::string> warnings;  ///< things the loader forgave, to be reported by the caller

  int64_t triangleCount() const { return static_cast<int64_t>(triangles.size()); }
  bool hasLabels() const { return !label.empty() && label.size() == triangles.size(); }
  Vec3 corner(int64_t t, int k) const { return vertices[triangles[t][k]]; }
  double area(int64_t t) const;
  Vec3 normal(int64_t t) const;  ///< unit, right-hand rule (the lit side)
  Vec3 centroid(int64_t t) const;
  void boundingBox(Vec3& lo, Vec3& hi) const;
  double totalArea() const;
};

/// Loads `spec`: a path (.obj with its .mtl) or "builtin:NAME?key=value&...". Validates
/// everything (finite coordinates, 0 ≤ ρ ≤ 1, E ≥ 0, indices in range) and throws InputError
/// naming file and line. Deterministic, so every rank may call it and get the same mesh.
Mesh loadScene(const std::string& spec);

/// The names accepted after "builtin:".
std::vector<std::string> builtinSceneNames();

/// A built-in scene as loadScene() reads it: its name and every parameter, defaults filled in.
struct BuiltinSpec {
  std::string name;
  std::map<std::string, double> parameters;
};
/// nullopt when `spec` is not "builtin:..."; an unknown scene or bad parameter throws
/// InputError exactly as loadScene() does.
std::optional<BuiltinSpec> parseBuiltinSpec(const std::string& spec);

/// Writes `mesh` as OBJ with an MTL beside it (one material per distinct ρ/E), so that
/// loadScene() of the written file gives the same triangles. Serial; call on one rank.
/// A similarity (translation and scale) taking a mesh's bounding box to centre 0 and diagonal
/// 1. Embree traces in float, and at coordinates of 1e18 or 1e-25 its arithmetic overflows or
/// underflows (every ray escaped at 1e18); radiosity is scale-free, so tracing in this frame
/// gives the answer of any scale. Directions are unchanged; lengths divide by `scale`.
struct TracingFrame {
  Vec3 centre{0, 0, 0};
  double scale = 1;
  Vec3 toFrame(Vec3 p) const { return (1.0 / scale) * (p - centre); }
};

/// Moves the mesh's vertices into its TracingFrame (in place) and returns the frame.
TracingFrame normaliseForTracing(Mesh& mesh);

void writeSceneObj(const Mesh& mesh, const std::string& objPath);

/// The solver's convergence history, the same on every rank (rank 0's is written):
/// one entry per iteration of each channel solved. Stored as /solve/history, float64 [n,4]
/// with columns channel (0 red, 1 green, 2 blue), iteration, relative residual, seconds since
/// the start of the solve; the dataset's attribute `columns` names them.
struct SolveHistory {
  std::vector<int> channel;
  std::vector<int64_t> iteration;
  std::vector<double> residual;
  std::vector<double> seconds;
  size_t size() const { return residual.size(); }
};

/// Everything stored at the root of a result file besides the datasets.
struct ResultAttributes {
  int formatVersion = 1;
  int ranks = 1;
  int64_t raysPerPatch = 0;
  uint64_t seed = 0;
  std::string solver;
  std::string leftOut = "none";  ///< work the scene did not need (stored as `left_out`)
  int64_t iterations = 0;        ///< summed over the channels solved
  double residual = 0;           ///< largest relative residual over the channels
  bool converged = false;
  std::string scene;                           ///< the SCENE argument
  std::string options;                         ///< the options used, one "name = value" per line
  std::map<std::string, double> stageSeconds;  ///< stored as "time_<stage>"
  /// Written only if non-empty (then all four columns must have the same length, channels in
  /// 0..2, iterations in [0, 2^53] so that float64 holds them exactly); read back empty if the
  /// file has no /solve/history.
  SolveHistory history;
  std::map<std::string, double> solveFigures;  ///< stored as float64 "solve_<key>"
  std::string solverChoice;                    ///< stored as `solver_choice`, only if non-empty
};

/// This rank's rows of the solution: patches [firstPatch, firstPatch + radiosity.size()).
struct LocalSolution {
  int64_t firstPatch = 0;
  std::vector<Rgb> radiosity;
  std::vector<Rgb> irradiance;
  /// Estimated standard error (sampling error) of B per patch and channel, each finite and ≥ 0,
  /// written as /patches/radiosity_stderr float64 [np,3]. If any rank has it, every rank must
  /// give one row per patch it owns (radiosity.size() rows).
  std::vector<Rgb> radiosityStderr;  ///< this rank's rows; empty on every rank: not written
  /// Estimated discretisation error of B per patch and channel (signed: the estimated true B
  /// minus B), written as /patches/radiosity_discretisation float64 [np,3] under the same rules.
  std::vector<Rgb> radiosityDiscretisation;
};

/// Rows [firstRow, firstRow + rowCount()) of a sparse matrix in CSR form: row r holds the
/// columns column[rowStart[r] .. rowStart[r+1]) with their values; rowStart[0] = 0.
struct MatrixRows {
  int64_t firstRow = 0;
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<double> value;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
  int64_t nonzeros() const { return static_cast<int64_t>(column.size()); }
};

/// Exact sample sums behind rows of F (formfactor's SampleTally): row r (patch firstRow + r)
/// holds columns column[rowStart[r] .. rowStart[r+1]) with sum = Σ contributions · 2^32 over
/// `samples` samples, so that F_ij = sum / (2^32 · samples) and more samples simply add up.
struct TallyRows {
  int64_t firstRow = 0;
  int64_t samples = 0;  ///< samples per row behind the sums
  std::vector<int64_t> rowStart{0};
  std::vector<int64_t> column;
  std::vector<int64_t> sum;
  int64_t rowCount() const { return static_cast<int64_t>(rowStart.size()) - 1; }
};

/// What the result file may hold about F, under /formfactors.
struct FormFactorOutput {
  /// Patches per bin of Σ_j F_ij over all rows (the same on every rank; rank 0's is written)
  /// and the bin edges: /formfactors/row_sum_histogram and row_sum_bin_edges. Empty: not
  /// written.
  std::vector<int64_t> rowSumHistogram;
  std::vector<double> rowSumBinEdges;
  /// This rank's rows of F (firstRow = LocalSolution::firstPatch), written as the global CSR
  /// arrays /formfactors/{row_start,column,value}; null on every rank: not written. Not owned.
  const MatrixRows* rows = nullptr;
};

/// Writes the result file of CONTRACT.md collectively: each rank writes its own slab of the
/// patch datasets (and a share of the vertices, and its own rows of F if given), nothing is
/// gathered. The file is written complete under the temporary name `outputs` gives it and
/// appears under `path` only at outputs.commit(), together with the command's other outputs;
/// on failure nothing is left and an existing `path` is untouched. Throws Error(kFailure).
/// Collective on outputs.comm().
void stageResult(CollectiveOutputs& outputs, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes,
                 const FormFactorOutput& formFactors = {});
/// stageResult() and commit, for a result written alone.
void writeResult(MPI_Comm comm, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes,
                 const FormFactorOutput& formFactors = {});

/// A whole result file in memory.
struct Result {
  Mesh mesh;  ///< patches with their ρ and E
  std::vector<double> area;
  std::vector<Vec3> normal;
  std::vector<Rgb> radiosity;
  std::vector<Rgb> irradiance;
  /// /patches/radiosity_stderr: the estimated standard error of B (finite, ≥ 0).
  std::vector<Rgb> radiosityStderr;  ///< empty if the file has none
  /// /patches/radiosity_discretisation: the estimated discretisation error of B (signed, finite).
  std::vector<Rgb> radiosityDiscretisation;  ///< empty if the file has none
  std::vector<int32_t> rank;
  ResultAttributes attributes;  ///< with history, solveFigures, solverChoice as in the file
  std::vector<int64_t> rowSumHistogram;  ///< empty if the file has none
  std::vector<double> rowSumBinEdges;
  std::optional<MatrixRows> formFactors;  ///< all rows of F (firstRow 0), if the file has them
};

/// Reads a result file whole on the calling process (serial HDF5). Throws InputError.
Result readResult(const std::string& path);

/// A human-readable listing of a result file: datasets with shapes, attributes, a summary.
std::string describeResult(const std::string& path);

/// The state of an interrupted (or finished) `radiosity solve`: this rank's share of it.
struct Checkpoint {
  std::string stage;  ///< "formfactors", "solve" or "done": the stage running when written
  /// What a restart must match, name → value (the scene's fingerprint, meshing, sampling and
  /// solver options); the same on every rank (rank 0's is written).
  std::map<std::string, std::string> identity;
  int64_t patchCount = 0;
  /// This rank's rows [rows.firstRow, rows.firstRow + rows.rowCount()). Rows may have different
  /// numbers of samples (a restart with more rays extends rows one piece at a time), so these
  /// are per row in rowSamples; rows.samples is not used (not written; the reader sets it to the
  /// largest of this rank's rowSamples, 0 if none).
  TallyRows rows;
  /// samples behind each of this rank's rows (0: not sampled yet, the row is then empty);
  /// rows.samples is not used
  std::vector<int64_t> rowSamples;
  /// The solve, per channel: 0 not started, 1 in progress, 2 done; B of this rank's rows (done
  /// channels: the answer; the channel in progress: its iterate; others: 0) and the history so
  /// far (rank 0's is written).
  std::array<int, 3> channelState{};
  std::vector<Rgb> radiosity;
  SolveHistory history;
  int64_t rowsFinished() const;  ///< of this rank's rows: those with rowSamples > 0
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

/// True if `path` is an HDF5 file written by writeCheckpoint (serial; any rank).
bool isCheckpoint(const std::string& path);
/// For `radiosity info`: stage, identity, rows sampled of all patches, the distinct numbers of
/// samples per row (with their row counts), channel states, history length. Serial.
std::string describeCheckpoint(const std::string& path);

}  // namespace radiosity
