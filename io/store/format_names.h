// The names the program's three HDF5 files share (the result file, the checkpoint, the scene
// file), written once. Each file's own header takes the ones it uses from here and adds its own:
// result_format.h (public: the result is the program's output), and io/store's private
// checkpoint_format.h and scene_file_format.h.
#pragma once

#include <array>

namespace radiosity::format_names {

/// Attribute names.
namespace attribute {
/// Of the root: what the file is (checkpoint and scene file), its version, the scene's length
/// unit where stated, and software_<name>: what made the file.
inline constexpr char kKind[] = "kind", kFormatVersion[] = "format_version",
                      kLengthUnit[] = "length_unit", kSoftwarePrefix[] = "software_";
/// Of every dataset; `columns` of /solve/history.
inline constexpr char kUnits[] = "units", kDescription[] = "description", kColumns[] = "columns";
}  // namespace attribute

/// The mesh: float64 [nv, 3] vertices, int64 [nt, 3] triangles (result and scene file).
inline constexpr char kMesh[] = "/mesh", kVertices[] = "/mesh/vertices",
                      kTriangles[] = "/mesh/triangles";
/// F in CSR form (result and checkpoint): int64 [np + 1] row starts, int64 [nnz] columns.
inline constexpr char kFormFactors[] = "/formfactors", kRowStart[] = "/formfactors/row_start",
                      kColumn[] = "/formfactors/column";
/// The convergence history (result and checkpoint): float64 [n, 4], its columns named so.
inline constexpr char kSolve[] = "/solve", kHistory[] = "/solve/history";
inline constexpr std::array<const char*, 4> kHistoryColumns = {"channel", "iteration", "residual",
                                                               "seconds"};

}  // namespace radiosity::format_names
