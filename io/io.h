// io: the scene in (OBJ+MTL, built-in scenes) and the result out (HDF5), plus the small geometry
// types every stage shares. HDF5 stays behind this header; MPI appears only as a communicator.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

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

/// Writes `mesh` as OBJ with an MTL beside it (one material per distinct ρ/E), so that
/// loadScene() of the written file gives the same triangles. Serial; call on one rank.
void writeSceneObj(const Mesh& mesh, const std::string& objPath);

/// Everything stored at the root of a result file besides the datasets.
struct ResultAttributes {
  int formatVersion = 1;
  int ranks = 1;
  int64_t raysPerPatch = 0;
  uint64_t seed = 0;
  std::string solver;
  int64_t iterations = 0;  ///< summed over the channels solved
  double residual = 0;     ///< largest relative residual over the channels
  bool converged = false;
  std::string scene;                           ///< the SCENE argument
  std::string options;                         ///< the options used, one "name = value" per line
  std::map<std::string, double> stageSeconds;  ///< stored as "time_<stage>"
};

/// This rank's rows of the solution: patches [firstPatch, firstPatch + radiosity.size()).
struct LocalSolution {
  int64_t firstPatch = 0;
  std::vector<Rgb> radiosity;
  std::vector<Rgb> irradiance;
};

/// Writes the result file of CONTRACT.md collectively: each rank writes its own slab of the
/// patch datasets (and a share of the vertices), nothing is gathered. The file appears under
/// `path` only when complete (written to a temporary name, then renamed); on failure nothing is
/// left and an existing `path` is untouched. Collective on `comm`.
void writeResult(MPI_Comm comm, const std::string& path, const Mesh& patches,
                 const LocalSolution& local, const ResultAttributes& attributes);

/// A whole result file in memory.
struct Result {
  Mesh mesh;  ///< patches with their ρ and E
  std::vector<double> area;
  std::vector<Vec3> normal;
  std::vector<Rgb> radiosity;
  std::vector<Rgb> irradiance;
  std::vector<int32_t> rank;
  ResultAttributes attributes;
};

/// Reads a result file whole on the calling process (serial HDF5). Throws InputError.
Result readResult(const std::string& path);

/// A human-readable listing of a result file: datasets with shapes, attributes, a summary.
std::string describeResult(const std::string& path);

}  // namespace radiosity
