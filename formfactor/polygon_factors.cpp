// Lambert's point-to-polygon view factor, integrated over the other triangle by Gauss rules.
// The closed form is exact for each point, so the only error is the quadrature's: the
// integrand is smooth where j is far from i (a rule of three points or seven suffices) and has a
// log-singular derivative along an edge the two triangles share, where i is halved until two
// levels agree.
#include "formfactor/polygon_factors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::formfactor {

namespace {

// The angle atan2(sine, cosine) in [0, π] for sine ≥ 0, to 1e-11: glibc's atan2 took 70 % of
// the time, much of it in its slow path for correctly rounded results the sum does not need.
// Reduced to [0, tan(π/8)], where the Taylor series to x^23 is within 1e-11.
inline double angleOf(double sine, double cosine) {
  const double across = std::abs(cosine);
  const bool steep = sine > across;
  double t = steep ? across / sine : sine / across;  // in [0, 1]
  const bool upper = t > 0.41421356237309503;        // tan(π/8)
  if (upper) t = (t - 1) / (t + 1);                  // atan t = π/4 + atan((t − 1)/(t + 1))
  // Σ_k (−1)^k u^k / (2k + 1), k ≤ 11, u = t², by Estrin's scheme: a few dependent steps
  // instead of eleven.
  const double u = t * t, u2 = u * u, u4 = u2 * u2, u8 = u4 * u4;
  const double q0 = 1 - u / 3, q1 = 1.0 / 5 - u / 7, q2 = 1.0 / 9 - u / 11;
  const double q3 = 1.0 / 13 - u / 15, q4 = 1.0 / 17 - u / 19, q5 = 1.0 / 21 - u / 23;
  const double p = (q0 + q1 * u2) + (q2 + q3 * u2) * u4 + (q4 + q5 * u2) * u8;
  double angle = p * t;
  if (upper) angle += std::numbers::pi / 4;
  if (steep) angle = std::numbers::pi / 2 - angle;
  return cosine < 0 ? std::numbers::pi - angle : angle;
}

}  // namespace

double pointToTriangleFactor(Vec3 x, Vec3 n, const Triangle& t) {
  const Vec3 r[3] = {t[0] - x, t[1] - x, t[2] - x};
  double sum = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = r[k], b = r[(k + 1) % 3];
    const Vec3 c = cross(a, b);
    const double sine = length(c);  // |a||b| sin(angle)
    // x on the line of the edge: the edge subtends no solid angle (or x is on it, which the
    // interior points of a triangle that only touches j never are).
    if (!(sine > 0)) continue;
    sum += angleOf(sine, dot(a, b)) * (dot(n, c) / sine);
  }
  return std::abs(sum) / (2 * std::numbers::pi);
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

// Strang and Fix's three-point rule, exact for polynomials of degree 2: f at its points (the
// mean of the three is the rule).
std::array<double, 3> atThreePoints(const Triangle& t, const Integrand& f) {
  constexpr double kNear = 2.0 / 3, kFar = 1.0 / 6;
  return {f(at(t, kNear, kFar, kFar)), f(at(t, kFar, kNear, kFar)), f(at(t, kFar, kFar, kNear))};
}

double sevenPointMean(const Triangle& t, const Integrand& f) {
  return kCentreWeight * f(at(t, 1.0 / 3, 1.0 / 3, 1.0 / 3)) +
         kW1 * (f(at(t, kA1, kB1, kB1)) + f(at(t, kB1, kA1, kB1)) + f(at(t, kB1, kB1, kA1))) +
         kW2 * (f(at(t, kA2, kB2, kB2)) + f(at(t, kB2, kA2, kB2)) + f(at(t, kB2, kB2, kA2)));
}

std::array<Triangle, 4> quarters(const Triangle& t) {
  const Vec3 m01 = 0.5 * (t[0] + t[1]), m12 = 0.5 * (t[1] + t[2]), m20 = 0.5 * (t[2] + t[0]);
  return {{{t[0], m01, m20}, {m01, t[1], m12}, {m20, m12, t[2]}, {m01, m12, m20}}};
}

// A bound on the halvings, for integrands that never settle (a shared edge converges slowly,
// the error near it falling a few times a level): the pieces are then 4^-14 of i.
constexpr int kMaxDepth = 14;

// The mean of f over t, given the seven-point mean `coarse`: accepted when the four quarters
// agree with it to `absolute`, else each quarter is refined the same way.
double adaptiveMean(const Triangle& t, double coarse, const Integrand& f, double absolute,
                    int depth) {
  const auto parts = quarters(t);
  double means[4], fine = 0;
  for (int k = 0; k < 4; ++k) fine += (means[k] = sevenPointMean(parts[k], f)) / 4;
  if (std::abs(fine - coarse) <= absolute || depth >= kMaxDepth) return fine;
  double refined = 0;
  for (int k = 0; k < 4; ++k) refined += adaptiveMean(parts[k], means[k], f, absolute, depth + 1);
  return refined / 4;
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

PairFactor triangleToTriangleFactor(const PatchShape& i, const PatchShape& j, double tolerance) {
  const Integrand f{i.normal, j.corners};
  // A lower bound on the distance from any point of i to any point of j; the integrand varies
  // over lengths of that order, so a rule's error falls as a power of i.radius / gap.
  const double gap = length(j.centroid - i.centroid) - i.radius - j.radius;
  const std::array<double, 3> points = atThreePoints(i.corners, f);
  if (gap > kThreePointGap * i.radius) return {points, (points[0] + points[1] + points[2]) / 3};
  const double coarse = sevenPointMean(i.corners, f);
  if (gap > kSevenPointGap * i.radius) return {points, coarse};
  return {points,
          adaptiveMean(i.corners, coarse, f, std::max(tolerance * coarse, kAbsoluteFloor), 0)};
}

}  // namespace radiosity::formfactor
