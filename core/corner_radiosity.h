// Smooth shading: radiosity at each patch corner, averaged over the patches around the vertex
// that lie in the same surface (a crease, a change of material stays sharp), and the
// interpolation inside a patch. The renderer shades with it, the discretisation error compares
// against it, and the result file's display mesh (/display, for ParaView) carries it as point
// data.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/mesh.h"

namespace radiosity {

/// Radiosity at the three corners of every patch, indexed [patch][corner].
using CornerRadiosity = std::vector<std::array<Rgb, 3>>;

/// Patches whose normals differ by more than this are not averaged: a crease stays sharp.
inline constexpr double kCreaseDegrees = 30;

/// Which smooth surface each patch lies in, for cornerRadiosity(): one id per patch, equal ids
/// for patches that may be averaged with each other.
using SurfaceIds = std::vector<int64_t>;

/// B = E + ρH jumps wherever E or ρ does, even between coplanar patches sharing an edge (a light
/// in its ceiling opening, a red patch on a white wall): patches share an id exactly when their
/// reflectance and emission are equal in every channel. Compared by value, not by material name:
/// two names with the same values are one surface to the light as well. Other lines B jumps
/// across (a contact line, the edge of the patches hidden under an object) split surfaces further
/// by ids of the caller's, combined with these; a line that ends inside a surface, as a shadow
/// boundary may, cannot be said by ids per patch. Throws std::invalid_argument unless the mesh
/// has a reflectance and an emission per triangle.
SurfaceIds materialSurfaces(const Mesh& mesh);

/// `ids` with every patch flagged in `apart` (1) made a surface of its own: the patches hidden
/// under an object or inside a solid (/patches/hidden), whose B = E says nothing of the lit
/// surface beside them. An empty `apart` changes nothing.
SurfaceIds setApart(SurfaceIds ids, const std::vector<uint8_t>& apart);

/// Every patch in one surface: averaged across everything but creases.
inline SurfaceIds oneSurface(const Mesh& mesh) { return SurfaceIds(mesh.triangles.size(), 0); }

/// Each corner's value is the area-weighted mean of `value` over the patches that share the
/// vertex (by position, so duplicated vertices count as one), have the patch's own surface id
/// (`surfaceOf`) and a normal within `creaseDegrees` of its own; the patch itself always counts.
/// `normal`, `area`, `value` and `surfaceOf` hold one entry per triangle of `mesh` (a
/// `surfaceOf` of another size throws std::invalid_argument).
CornerRadiosity cornerRadiosity(const Mesh& mesh, const std::vector<Vec3>& normal,
                                const std::vector<double>& area, const std::vector<Rgb>& value,
                                const SurfaceIds& surfaceOf, double creaseDegrees = kCreaseDegrees);

/// The gradient of a per-patch value inside each patch, indexed [patch][channel]: a vector in the
/// patch's plane, so that value[t] + g·(x − centroid) is a linear reconstruction with the patch's
/// own mean. Fitted by least squares to the differences towards the patches that share a vertex
/// with it and join it as in cornerRadiosity() (same surface id, normal within `creaseDegrees`),
/// each weighted by 1/distance². Unlike corner averages, it extrapolates to a surface's edge
/// (a crease, a contact line, the edge of a plate) instead of flattening there: at an edge a corner
/// is the mean of the patches beside it, and the slope towards the edge comes out half. Zero where
/// the neighbours span no direction (a patch alone in its surface). Only patches [first, last)
/// (last < 0: to the end), entry t − first for patch t: a rank fits its own rows, and each row's
/// gradient is the same whichever rows are asked for.
using PatchGradients = std::vector<std::array<Vec3, 3>>;
PatchGradients patchGradients(const Mesh& mesh, const std::vector<Vec3>& normal,
                              const std::vector<Rgb>& value, const SurfaceIds& surfaceOf,
                              int64_t first = 0, int64_t last = -1,
                              double creaseDegrees = kCreaseDegrees);

/// Per-patch values of part of the scene: a block of consecutive patches, and some others by id
/// (what a rank holds of the scene: its rows and their neighbours). Keeps a reference to `block`.
class PatchValues {
 public:
  /// Every patch's, from a scene-wide array.
  PatchValues(const std::vector<Rgb>& all) : first_(0), block_(all) {}  // NOLINT: a view
  /// Patches [first, first + block.size()) and `others` (sorted ids, one value each).
  PatchValues(int64_t first, const std::vector<Rgb>& block, std::vector<int64_t> others,
              std::vector<Rgb> otherValues);

  /// Patch p's value; p must be one of the held patches (std::out_of_range otherwise).
  const Rgb& operator[](int64_t p) const {
    const auto inBlock = static_cast<uint64_t>(p - first_);
    return inBlock < block_.size() ? block_[inBlock] : other(p);
  }

 private:
  const Rgb& other(int64_t p) const;
  int64_t first_;
  const std::vector<Rgb>& block_;
  std::vector<int64_t> others_;
  std::vector<Rgb> otherValues_;
};

/// patchGradients() one patch at a time: the patches around every vertex are found once, for as
/// many patches and value arrays as the caller asks, and nothing per patch is kept (the
/// discretisation estimate fits each of a rank's rows, and some again, without arrays of
/// gradients). Keeps references to `mesh`, `normal` and `surfaceOf`; without `normal`, each
/// patch's is the mesh's (Mesh::normal), and no array of the scene's normals is held.
class GradientFit {
 public:
  GradientFit(const Mesh& mesh, const std::vector<Vec3>& normal, const SurfaceIds& surfaceOf,
              double creaseDegrees = kCreaseDegrees);
  explicit GradientFit(const Mesh& mesh, const SurfaceIds& surfaceOf,
                       double creaseDegrees = kCreaseDegrees);
  /// Only for patches [first, last): the patches around their corners alone are found (a rank's
  /// rows, without the fans of the whole scene), and only those fit (others: std::out_of_range).
  GradientFit(const Mesh& mesh, const SurfaceIds& surfaceOf, int64_t first, int64_t last,
              double creaseDegrees = kCreaseDegrees);
  ~GradientFit();
  GradientFit(const GradientFit&) = delete;
  GradientFit& operator=(const GradientFit&) = delete;

  /// Patch t's gradient of `value` (one entry per patch, or at least t's and its neighbours'),
  /// per channel.
  std::array<Vec3, 3> operator()(int64_t t, const PatchValues& value) const;

  /// The patches outside [first, last) that the fits of patches [first, last) read, sorted:
  /// whose values a rank holding only its own rows needs from the others.
  std::vector<int64_t> neighboursOutside(int64_t first, int64_t last) const;

 private:
  struct Neighbours;
  const Mesh& mesh_;
  std::unique_ptr<const Neighbours> around_;
  int64_t first_ = 0, last_ = -1;  ///< the patches that can be fit (last_ < 0: all)
};

/// A mesh to show B smooth with a viewer's point data: one vertex per distinct pair of position
/// and corner value, so that corners in one surface share a vertex and the edge between two
/// surfaces splits it (a viewer interpolating point data then shades as the renderer does).
struct DisplayMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;  ///< one per patch, in the patches' order
  std::vector<Rgb> radiosity;       ///< per vertex
};
DisplayMesh displayMesh(const Mesh& mesh, const CornerRadiosity& corners);

/// The display mesh of a block of patches, from what a rank holds: the patches around the
/// corners of patches [first, last) alone are found (not the whole scene's fans), each patch's
/// normal and area are the mesh's, and B is read from PatchValues. Keeps references to `mesh`
/// and `surfaceOf`.
class CornerAverages {
 public:
  CornerAverages(const Mesh& mesh, const SurfaceIds& surfaceOf, int64_t first, int64_t last,
                 double creaseDegrees = kCreaseDegrees);
  ~CornerAverages();
  CornerAverages(const CornerAverages&) = delete;
  CornerAverages& operator=(const CornerAverages&) = delete;

  /// The patches outside [first, last) whose values the corners inside read, sorted.
  std::vector<int64_t> neighboursOutside() const;

  /// displayMesh() of patches [from, to) within [first, last) alone, its vertices numbered from
  /// 0: the same as the whole scene's where [from, to) is the whole scene. `value`: B of those
  /// patches and of their neighbours.
  DisplayMesh displayMesh(const PatchValues& value, int64_t from, int64_t to) const;

 private:
  struct Neighbours;
  std::unique_ptr<const Neighbours> around_;
  int64_t first_, last_;
};

/// The value at barycentric (u, v): (1-u-v)·c0 + u·c1 + v·c2, as SceneTracer::Hit reports them.
inline Rgb interpolate(const std::array<Rgb, 3>& corner, double u, double v) {
  double w = 1 - u - v;
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = w * corner[0][c] + u * corner[1][c] + v * corner[2][c];
  return out;
}

}  // namespace radiosity
