// The result file of a solve (HDF5; its format is in the README): written collectively, each
// rank its own slab, and read back whole.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "core/run_state.h"
#include "io/store/collective_outputs.h"
#include "io/store/result_format.h"

namespace radiosity {

/// Everything stored at the root of a result file besides the datasets.
struct ResultAttributes {
  int formatVersion = result_format::kFormatVersion;
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
  /// The scene's length unit ("m"), stored as `length_unit` and in the units of /mesh/vertices
  /// and /patches/area; empty: not known (not stored).
  std::string lengthUnit;
  /// Columns of the per-channel datasets (ρ, E, B, H and B's errors): 3 (red, green, blue), or
  /// 1 for a thermal run (the channels are alike; the first is written).
  int channels = 3;
  /// The thermal boundary-condition file of a thermal run (stored as `thermal`); empty: a
  /// lighting run. Then E, B and H are in W/m^2.
  std::string thermal;
  /// What made the file: the program's version and git revision and the libraries' versions,
  /// name → version, stored as text attributes "software_<name>".
  std::map<std::string, std::string> software;
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
  /// 1 where the patch sees nothing (formfactor::hiddenPatches: under an object resting on it,
  /// inside a solid), left out of the solve; written as /patches/hidden int8 [np] when any
  /// patch of any rank is hidden (then every rank gives one per patch it owns).
  std::vector<uint8_t> hidden;  ///< this rank's rows; empty or all 0 on every rank: not written
  /// The estimated errors of H per patch and channel, as of B above (sampling: a standard error;
  /// discretisation: signed), where ρ = 0 too; for the thermal figures, not written.
  std::vector<Rgb> irradianceStderr, irradianceDiscretisation;
  /// A thermal run's temperature (K) and net radiative heat flux leaving each patch (W/m^2),
  /// /patches/temperature and /patches/net_heat_flux; empty on every rank: not written.
  std::vector<double> temperature, netHeatFlux;
};

/// What the result file may hold about F, under /formfactors (and /groups).
struct FormFactorOutput {
  /// Patches per bin of Σ_j F_ij over all rows (the same on every rank; rank 0's is written)
  /// and the bin edges: /formfactors/row_sum_histogram and row_sum_bin_edges. Empty: not
  /// written.
  std::vector<int64_t> rowSumHistogram;
  std::vector<double> rowSumBinEdges;
  /// This rank's rows of F (firstRow = LocalSolution::firstPatch), written as the global CSR
  /// arrays /formfactors/{row_start,column,value}; null on every rank: not written. Not owned.
  const SparseRows* rows = nullptr;
  /// The same on every rank (rank 0's is written); empty: /groups not written.
  GroupFactors groups{};
  /// Or, instead of `rows`, F's one store (the same rows as SplitRows::values gives them),
  /// written from it a piece at a time, so that no copy of F is made for the file. Not owned.
  const SplitRows* store = nullptr;
};

/// Writes the result file (docs/result-format.md) collectively: each rank writes its own slab
/// of the patch datasets (and a share of the vertices, and its own rows of F if given), nothing
/// is gathered. The file is written complete under the temporary name `outputs` gives it and
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
  /// /patches/hidden: 1 where the patch sees nothing (left out of the solve: B = E, H = 0).
  std::vector<uint8_t> hidden;  ///< empty if the file has none (no patch hidden)
  std::vector<int32_t> rank;
  ResultAttributes attributes;  ///< with history, solveFigures, solverChoice as in the file
  std::vector<int64_t> rowSumHistogram;  ///< empty if the file has none
  std::vector<double> rowSumBinEdges;
  std::optional<SparseRows> formFactors;  ///< all rows of F (firstRow 0), if the file has them
  GroupFactors groups;                    ///< empty if the file has none
  std::vector<double> temperature, netHeatFlux;  ///< a thermal run's; empty otherwise
};

/// Reads a result file whole on the calling process (serial HDF5). Throws InputError.
Result readResult(const std::string& path);

/// A human-readable listing of a result file: datasets with shapes, attributes, a summary.
std::string describeResult(const std::string& path);
/// What describeResult lists, as JSON (`info --json`, docs/json-summaries.md), for any HDF5 file
/// of the program's (result, checkpoint, scene file): datasets, attributes, and for a result its
/// summary. Throws InputError.
std::string describeFileJson(const std::string& path);

}  // namespace radiosity
