// Lambert's point-to-polygon view factor, integrated over the other triangle by Gauss rules.
// The closed form is exact for each point, so the only error is the quadrature's: the
// integrand is smooth where j is far from i (a rule of three points or seven suffices); nearer,
// it varies over the distance between them, which no rule over i's area follows at a bounded
// cost, and the pair goes to the contour integral (formfactor/contour_factors.h).
#include "formfactor/polygon_factors.h"

#include "formfactor/contour_factors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::formfactor {

namespace {

// The angle atan2(sine, cosine) in [0, π] for sine ≥ 0, to 1e-11: glibc's atan2 took most of
// the time, much of it in its slow path for correctly rounded results the sum does not need.
// Reduced to [0, tan(π/8)], where the Taylor series to x^23 is within 1e-11.
// Free of branches (selects only), so that loops over it vectorise.
[[gnu::always_inline]] inline double angleOf(double sine, double cosine) {
  const double across = std::abs(cosine);
  const bool steep = sine > across;
  const double ratio = (steep ? across : sine) / (steep ? sine : across);  // in [0, 1]
  const bool upper = ratio > 0.41421356237309503;                          // tan(π/8)
  // atan t = π/4 + atan((t − 1)/(t + 1))
  const double t = upper ? (ratio - 1) / (ratio + 1) : ratio;
  // Σ_k (−1)^k u^k / (2k + 1), k ≤ 11, u = t², by Estrin's scheme: a few dependent steps
  // instead of eleven.
  const double u = t * t, u2 = u * u, u4 = u2 * u2, u8 = u4 * u4;
  const double q0 = 1 - u / 3, q1 = 1.0 / 5 - u / 7, q2 = 1.0 / 9 - u / 11;
  const double q3 = 1.0 / 13 - u / 15, q4 = 1.0 / 17 - u / 19, q5 = 1.0 / 21 - u / 23;
  const double p = (q0 + q1 * u2) + (q2 + q3 * u2) * u4 + (q4 + q5 * u2) * u8;
  const double angle = p * t + (upper ? std::numbers::pi / 4 : 0.0);
  const double quadrant = steep ? std::numbers::pi / 2 - angle : angle;
  return cosine < 0 ? std::numbers::pi - quadrant : quadrant;
}

// One edge's term of Lambert's sum, from the point to the edge's ends a and b: the angle the
// edge subtends times the cosine between n and the normal of the plane through the point and
// the edge. Zero where the point is on the edge's line: it subtends no solid angle there (and
// the interior points of a triangle that only touches the other are never on it).
[[gnu::always_inline]] inline double edgeTerm(Vec3 a, Vec3 b, Vec3 n) {
  const Vec3 c = cross(a, b);
  const double sine = std::sqrt(dot(c, c));  // |a||b| sin(angle)
  const double term = angleOf(sine, dot(a, b)) * (dot(n, c) / sine);
  return sine > 0 ? term : 0.0;
}

[[gnu::always_inline]] inline double lambert(Vec3 x, Vec3 n, Vec3 p0, Vec3 p1, Vec3 p2) {
  const Vec3 a = p0 - x, b = p1 - x, c = p2 - x;
  return std::abs(edgeTerm(a, b, n) + edgeTerm(b, c, n) + edgeTerm(c, a, n)) /
         (2 * std::numbers::pi);
}

// The points of Strang and Fix's three-point rule (exact for polynomials of degree 2).
constexpr double kRuleNear = 2.0 / 3, kRuleFar = 1.0 / 6;

}  // namespace

double pointToTriangleFactor(Vec3 x, Vec3 n, const Triangle& t) {
  return lambert(x, n, t[0], t[1], t[2]);
}

void TriangleTable::add(const Triangle& t) {
  for (int k = 0; k < 3; ++k) {
    x[k].push_back(t[k].x);
    y[k].push_back(t[k].y);
    z[k].push_back(t[k].z);
  }
}

// Compiled for AVX2 and for the baseline, picked at run time (as the ray-making loops): four
// triangles a step. No fused multiply-adds in either, so both give the same bits.
__attribute__((target_clones("avx2", "default"))) void threePointFactors(const PatchShape& i,
                                                                         const TriangleTable& table,
                                                                         double* __restrict first,
                                                                         double* __restrict second,
                                                                         double* __restrict third) {
  const Triangle& c = i.corners;
  const Vec3 n = i.normal;
  const Vec3 p0 = kRuleNear * c[0] + kRuleFar * c[1] + kRuleFar * c[2];
  const Vec3 p1 = kRuleFar * c[0] + kRuleNear * c[1] + kRuleFar * c[2];
  const Vec3 p2 = kRuleFar * c[0] + kRuleFar * c[1] + kRuleNear * c[2];
  const double* __restrict x0 = table.x[0].data();
  const double* __restrict y0 = table.y[0].data();
  const double* __restrict z0 = table.z[0].data();
  const double* __restrict x1 = table.x[1].data();
  const double* __restrict y1 = table.y[1].data();
  const double* __restrict z1 = table.z[1].data();
  const double* __restrict x2 = table.x[2].data();
  const double* __restrict y2 = table.y[2].data();
  const double* __restrict z2 = table.z[2].data();
  const size_t count = table.size();
  for (size_t j = 0; j < count; ++j) {
    const Vec3 v0{x0[j], y0[j], z0[j]}, v1{x1[j], y1[j], z1[j]}, v2{x2[j], y2[j], z2[j]};
    first[j] = lambert(p0, n, v0, v1, v2);
    second[j] = lambert(p1, n, v0, v1, v2);
    third[j] = lambert(p2, n, v0, v1, v2);
  }
}

bool inFrontOfPlane(const Triangle& t, Vec3 origin, Vec3 n, double slack) {
  bool beyond = false;
  for (const Vec3& corner : t) {
    const double height = dot(n, corner - origin);
    if (height < -slack) return false;
    beyond = beyond || height > slack;
  }
  return beyond;
}

namespace {

Vec3 at(const Triangle& t, double a, double b, double c) { return a * t[0] + b * t[1] + c * t[2]; }

// Radon's seven-point rule, exact for polynomials of degree 5: barycentric points and weights.
constexpr double kCentreWeight = 0.225;
constexpr double kA1 = 0.059715871789770, kB1 = 0.470142064105115, kW1 = 0.132394152788506;
constexpr double kA2 = 0.797426985353087, kB2 = 0.101286507323456, kW2 = 0.125939180544827;

struct Integrand {
  Vec3 n;
  const Triangle& j;
  double operator()(Vec3 x) const { return pointToTriangleFactor(x, n, j); }
};

double sevenPointMean(const Triangle& t, const Integrand& f) {
  return kCentreWeight * f(at(t, 1.0 / 3, 1.0 / 3, 1.0 / 3)) +
         kW1 * (f(at(t, kA1, kB1, kB1)) + f(at(t, kB1, kA1, kB1)) + f(at(t, kB1, kB1, kA1))) +
         kW2 * (f(at(t, kA2, kB2, kB2)) + f(at(t, kB2, kA2, kB2)) + f(at(t, kB2, kB2, kA2)));
}

double radiusAbout(const Triangle& t, Vec3 centre) {
  return std::max({length(t[0] - centre), length(t[1] - centre), length(t[2] - centre)});
}

}  // namespace

PatchShape::PatchShape(const Triangle& corners, Vec3 unitNormal)
    : corners(corners),
      normal(unitNormal),
      centroid((1.0 / 3) * (corners[0] + corners[1] + corners[2])),
      radius(radiusAbout(corners, centroid)) {}

double triangleToTriangleFactor(const PatchShape& i, const PatchShape& j,
                                const std::array<double, 3>& atRulePoints, double* error) {
  // A lower bound on the distance from any point of i to any point of j; the integrand varies
  // over lengths of that order, so a rule's error falls as a power of i.radius / gap.
  const double gap = length(j.centroid - i.centroid) - i.radius - j.radius;
  if (gap > kThreePointGap * i.radius) {
    return (atRulePoints[0] + atRulePoints[1] + atRulePoints[2]) / 3;
  }
  if (gap > kSevenPointGap * i.radius) return sevenPointMean(i.corners, {i.normal, j.corners});
  const ContourFactor near = contourFactor(i, j);
  if (error) *error = near.error;
  return near.value;
}

}  // namespace radiosity::formfactor
