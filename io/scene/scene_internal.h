// Private to io/: the pieces loadScene() is made of. Not part of the public interface.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::detail {

/// The material a face gets when its file gives none.
inline constexpr Rgb kDefaultReflectance = {0.5, 0.5, 0.5};

using radiosity::kMaxCoordinate;

/// Reads an OBJ file (and the MTL files it names). Throws InputError with file and line.
Mesh readObj(const std::string& path);

/// Reads a .ply or .off file through OpenMesh. Throws InputError naming the file.
Mesh readOpenMeshFile(const std::string& path);

/// Reads a binary or ASCII .stl file through OpenMesh, after a strict walk of its structure.
/// Throws InputError naming the file (and, for ASCII, the line).
Mesh readStl(const std::string& path);

/// Reads View3D's input file (.vs3, geometry format F 3): its surfaces, in order, become source
/// faces; names become labels; emissivities become ρ = 1 − ε. Throws InputError with file:line.
Mesh readVs3(const std::string& path);

/// Builds the built-in scene `spec` ("builtin:NAME?key=value&..."). Throws InputError.
Mesh buildBuiltinScene(const std::string& spec);

/// builtin:rooms: a near-square plan of rooms (about `patches` / 2000 of them) joined by doors,
/// each with a ceiling light of exitance `light`, a table and a shelf placed by `seed`,
/// tessellated so that the scene has `patches` triangles within a few per cent.
Mesh buildRooms(int64_t patches, uint64_t seed, double light);

/// builtin:city's geometry: perSide × perSide box buildings (footprints and heights in metres,
/// drawn by `seed`) on lots of pitch footprintMax + street, surfaces cut into cells of about
/// `element` metres.
struct CityLayout {
  int perSide;
  double street, footprintMin, footprintMax, heightMin, heightMax, element;
  uint64_t seed;
};
/// builtin:city's materials: one reflectance, and the exitance of the ground and the buildings.
struct CityMaterials {
  double rho, eGround, eBuilding;
};

/// builtin:city: box buildings without bottoms on a ground plane with holes under them, y up,
/// open to the sky. Labels: 0 "ground", k "building k" (k = 1 + i + perSide · j for the
/// building in column i along x and row j along z). Source faces: 0 the ground, 5k − 4 the roof
/// of building k, 5k − 3 … 5k its walls at low x, high x, low z, high z. `spec` names the scene
/// in messages. Throws InputError.
Mesh buildCity(const CityLayout& city, const CityMaterials& materials, const std::string& spec);

/// A polygon's triangles: index i < polygon.size() is corner i, polygon.size() + k is added[k],
/// a point inside it.
struct PolygonTriangulation {
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec3> added;
};

/// Splits a simple polygon (counter-clockwise about its own best-fit normal, possibly concave)
/// into triangles, keeping its winding. Ear clipping, without added points, unless that leaves
/// needles (aspect ratio above 10: a polygon of many corners, such as a disc, became a fan of
/// them) in a planar polygon: then a constrained Delaunay refinement with points added inside
/// (none on the outline, which neighbours share), if its worst triangle is better. A triangle
/// or a quad, and a convex polygon of few corners, gives the fan from vertex 0.
PolygonTriangulation triangulatePolygon(const std::vector<Vec3>& polygon);

/// Newell's normal of a polygon's outline: its area vector times 2, pointing to the side it
/// winds around counter-clockwise.
Vec3 newellNormal(const std::vector<Vec3>& polygon);

/// Whether `p`, taken into the plane of the planar `polygon`, lies inside its outline or within
/// `tolerance` of it.
bool insidePolygon(const std::vector<Vec3>& polygon, Vec3 p, double tolerance);

/// The planar polygon `outline` with the polygons `holes` cut out of it (inside it, in its
/// plane, winding as it does; they may share corners and edges with it and each other),
/// triangulated: index i < n counts the corners of the outline, then of each hole (a corner at
/// the point of an earlier one takes that one's index), n + k is added[k]; triangles wind as
/// the outline. The points are taken into the plane by dropping the coordinate along its
/// normal's largest component, so that corners of an axis-aligned wall lie exactly on the
/// edges they lie on in the file. nullopt where edges cross, or where the triangles' area is
/// not the outline's less the holes' (holes that overlap or leave the outline).
std::optional<PolygonTriangulation> triangulateWithHoles(
    const std::vector<Vec3>& outline, const std::vector<std::vector<Vec3>>& holes);

/// Vertices that triangulation added inside polygons, kept apart while a file is read (its own
/// vertex numbers, which later faces name, negative OBJ indices among them, must not move) and
/// appended after the file's vertices at the end.
class AddedVertices {
 public:
  /// The vertex indices of `polygon`'s triangles, `corners` being its corners' indices; the
  /// added points get placeholders (negative) until appendTo().
  std::vector<Triangle> triangles(const PolygonTriangulation& polygon,
                                  const std::vector<int64_t>& corners);
  /// Appends the added points to mesh.vertices and puts their indices in mesh.triangles.
  void appendTo(Mesh& mesh) const;

 private:
  std::vector<Vec3> points_;
};

/// Whether two edges of the polygon's outline that do not share a corner cross each other in
/// its plane (a "bowtie"): no triangulation covers such an outline as the user meant, and the
/// ear clipper would return opposite-facing triangles.
bool crossesItself(const std::vector<Vec3>& polygon);

/// A face's repeated vertex index, if any (the corner that first repeats an earlier one).
/// O(n log n): a face may have tens of thousands of corners.
std::optional<int64_t> repeatedCorner(const std::vector<int64_t>& corners);

/// The refusal of a face of more than 3 corners that names `vertex` twice (the caller adds
/// where): its outline is ambiguous, so it is not guessed at.
std::string repeatedCornerProblem(const std::string& face, int64_t vertex);

}  // namespace radiosity::detail
