// Private to formfactor/: view factors between triangles that see each other whole, with no
// occluder between them, by Lambert's closed form for a point and a polygon integrated over the
// emitting triangle (Gauss rules), or for pairs near each other by the integral around both
// triangles' edges (formfactor/contour_factors.h). Deterministic:
// the rows of a convex scene (formfactor/exact_rows.cpp) are made of them, with no rays.
#pragma once

#include <array>
#include <vector>

#include "core/vec3.h"

namespace radiosity::formfactor {

using Triangle = std::array<Vec3, 3>;

/// F from the point x with unit normal n to the triangle t, every corner of t on or in front of
/// the plane through x (Lambert: (1/2π) Σ over t's edges of the angle the edge subtends times
/// the cosine between n and the normal of the plane through x and the edge). Exact.
double pointToTriangleFactor(Vec3 x, Vec3 n, const Triangle& t);

/// A triangle with what the quadrature asks of it again and again.
struct PatchShape {
  PatchShape(const Triangle& corners, Vec3 unitNormal);
  Triangle corners;
  Vec3 normal;  ///< unit, the lit side
  Vec3 centroid;
  double radius;  ///< of the sphere about the centroid through the farthest corner
};

/// Gaps between the bounding spheres of i and j, in radii of i, beyond which three points
/// (Strang and Fix's degree-2 rule) or seven (Radon's degree-5 rule) are enough; nearer, the
/// contour integral, to kContourTolerance (halving i until two levels agreed to 1e-4 of F_ij
/// failed for nearly touching plates: levels agreeing by chance left rows summing to 1.001, and
/// thousands of pieces along the other's edges took a minute). The centroid alone overestimates
/// the far pairs, all with one sign, and a closed scene's rows then sum visibly above 1: too far
/// for a reflectance near 1.
inline constexpr double kThreePointGap = 8;
inline constexpr double kSevenPointGap = 1;

/// Triangles as structure of arrays (corner k at x[k][t], y[k][t], z[k][t]), for loops that
/// vectorise.
struct TriangleTable {
  std::array<std::vector<double>, 3> x, y, z;
  void add(const Triangle& t);
  size_t size() const { return x[0].size(); }
};

/// pointToTriangleFactor from each of the three points of the degree-2 rule on i (Strang and
/// Fix) to every triangle of the table, into first/second/third[0 .. table.size()), whatever
/// the triangles' distance and side (those not in front of i get meaningless values): a row's
/// bulk, vectorised. The same three points for every j, so that summed over a row they give,
/// to round-off, the share of each point's hemisphere the patches cover (Lambert's formula is
/// exact for each point): 1 at each where the patches close the scene around i.
void threePointFactors(const PatchShape& i, const TriangleTable& table, double* first,
                       double* second, double* third);

/// F_ij from triangle i to triangle j, j on or in front of i's plane, i on or in front of j's
/// and nothing between them: the mean of pointToTriangleFactor over i, given its values at the
/// three points of threePointFactors (the rule where j is far). `error`, where given, is set to
/// the contour integral's estimate of its error for a near pair (and left alone otherwise).
double triangleToTriangleFactor(const PatchShape& i, const PatchShape& j,
                                const std::array<double, 3>& atRulePoints, double* error = nullptr);

/// Whether the corners of `t` lie on or in front of the plane through `origin` with unit normal
/// `n`, within `slack` (a length), with at least one beyond `slack` in front.
bool inFrontOfPlane(const Triangle& t, Vec3 origin, Vec3 n, double slack);

}  // namespace radiosity::formfactor
