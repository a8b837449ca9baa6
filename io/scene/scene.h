// Scene input: OBJ+MTL, PLY, OFF, STL, View3D's .vs3 and the built-in scenes, validated, and the
// OBJ writer.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"

namespace radiosity {

/// Loads `spec`: a path (.obj with its .mtl, .ply, .off, .stl, View3D's .vs3) or
/// "builtin:NAME?key=value&...". Validates everything (finite coordinates, 0 ≤ ρ ≤ 1, E ≥ 0,
/// indices in range) and throws InputError naming file and line. Deterministic, so every rank may
/// call it and get the same mesh. An HDF5 scene file (isHdf5Scene) is read by all ranks together,
/// through loadScene(spec, comm) of io/store/scene_file.h, which takes every other spec too.
Mesh loadScene(const std::string& spec);

/// Whether `spec` names an HDF5 scene file: a path ending in .h5 or .hdf5 (in any case).
bool isHdf5Scene(const std::string& spec);

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

/// Checks what every scene must satisfy and drops degenerate triangles (with one warning).
/// `source` names the scene in messages. Throws InputError.
void validateScene(Mesh& mesh, const std::string& source);

/// validateScene's rule for degenerate triangles, for a reader that checked the rest itself and
/// applies it to a share of the triangles (the HDF5 scene reader of io/store/): triangle t is
/// degenerate if it has no area or its height over its longest edge is at most
/// kDegenerateHeight times that edge. Judged per triangle, whatever the rest of the scene.
bool isDegenerate(const Mesh& mesh, int64_t t);
inline constexpr double kDegenerateHeight = 1e-12;
/// Smaller triangle areas are refused (scale the scene up): near the smallest normal double
/// (2.2e-308), E·A and sums of areas lose their digits.
inline constexpr double kMinArea = 1e-305;

/// Writes `mesh` as OBJ with an MTL beside it (one material per distinct ρ/E), so that
/// loadScene() of the written file gives the same triangles. Serial; call on one rank.
void writeSceneObj(const Mesh& mesh, const std::string& objPath);

}  // namespace radiosity
