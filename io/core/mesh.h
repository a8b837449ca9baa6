// The triangle mesh every stage shares: the scene as loaded and the patches after meshing.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/core/vec3.h"

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
  std::vector<std::string> warnings;  ///< things the loader forgave, to be reported by the caller
  /// The length unit of the coordinates ("m", "mm") where the scene states it (the built-in
  /// scenes, or --length-unit); empty: not known.
  std::string lengthUnit;
  /// The files the scene was read from (the scene file, then each MTL it names); empty for a
  /// built-in scene and for patches. Outputs must be none of them (jobs/output_paths.h).
  std::vector<std::string> sourceFiles;

  int64_t triangleCount() const { return static_cast<int64_t>(triangles.size()); }
  bool hasLabels() const { return !label.empty() && label.size() == triangles.size(); }
  Vec3 corner(int64_t t, int k) const { return vertices[triangles[t][k]]; }
  double area(int64_t t) const;
  Vec3 normal(int64_t t) const;  ///< unit, right-hand rule (the lit side)
  Vec3 centroid(int64_t t) const;
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

}  // namespace radiosity
