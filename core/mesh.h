// The triangle mesh every stage shares: the scene as loaded and the patches after meshing.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace radiosity {

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
  /// Per label, the emissivity the scene file states for it (a View3D .vs3 surface's), which a
  /// thermal boundary condition without `emissivity` takes; NaN where the file states none (or
  /// its parts differ). Empty: the scene states no emissivities. Not stored in result files.
  std::vector<double> labelEmissivity;
  std::vector<std::string> warnings;  ///< things the loader forgave, to be reported by the caller
  /// The length unit of the coordinates ("m", "mm") where the scene states it (the built-in
  /// scenes, or --length-unit); empty: not known.
  std::string lengthUnit;
  /// The files the scene was read from (the scene file, then each MTL it names); empty for a
  /// built-in scene and for patches. Outputs must be none of them (run/output_paths.h).
  std::vector<std::string> sourceFiles;

  int64_t triangleCount() const { return static_cast<int64_t>(triangles.size()); }
  bool hasLabels() const { return !label.empty() && label.size() == triangles.size(); }
  Vec3 corner(int64_t t, int k) const { return vertices[triangles[t][k]]; }
  double area(int64_t t) const;
  Vec3 normal(int64_t t) const;  ///< unit, right-hand rule (the lit side)
  Vec3 centroid(int64_t t) const;
  /// Of the vertices the triangles use: a vertex no triangle names (an OBJ's stray `v 1e30 0 0`)
  /// must not squeeze the scene in its tracing frame. lo = +inf, hi = -inf for no triangles.
  void boundingBox(Vec3& lo, Vec3& hi) const;
  double totalArea() const;
};

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

/// Float tracing resolves a triangle only if its longest edge is at least this share of its
/// corners' distance from the centre of the triangles' bounding box: rays start off a surface
/// by that share of its distance (what float rounding there needs: trace::SceneTracer::
/// offset), and from a smaller triangle they would start beyond it (a unit room at the edge of
/// a ground plane 1e6 wide; the rest of a scene with one vertex at 1e30).
inline constexpr double kTraceableShare = 1e-5;

/// Larger emission is refused: the solver's norms square B (Σ B² over the patches), which
/// overflows near 1e154 (E = 1e160 ended in "iterate is not finite"); 1e100 leaves room for
/// ρ close to 1 (B = E / (1 − ρ)) and 10^8 patches. Radiosity is linear in E: scale it down
/// and the answer up. docs/stability.md.
inline constexpr double kMaxEmission = 1e100;

/// Larger coordinates are refused: squared lengths and cross products must stay finite.
inline constexpr double kMaxCoordinate = 1e30;

/// A triangle of `mesh` float tracing cannot resolve (kTraceableShare), or -1 if none; sets
/// `size` to its longest edge and `distance` to its farthest corner's from the centre. A
/// triangle cut from a source face (sourceFace) that is itself large enough passes: the pieces
/// the mesh cuts (the slivers along a contact line) are traced as their face is.
int64_t untraceableTriangle(const Mesh& mesh, double& size, double& distance);

/// Why the triangles of `mesh` cannot be traced (a corner not finite or beyond kMaxCoordinate,
/// an untraceableTriangle), "" if they can: what the render and verify tracers refuse in a
/// result as the loaders do in a scene (Embree aborted on a result vertex at 1e31).
std::string tracingProblem(const Mesh& mesh);

}  // namespace radiosity
