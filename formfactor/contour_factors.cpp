// Sparrow's contour integral: A_i F_ij = (1/2π) ∮_i ∮_j ln r dx_i·dx_j, both edges run
// counter-clockwise about their triangle's normal. The inner integral along an edge of j is
// closed (∫ ln √(s² + h²) ds); the outer, along an edge of i, is continuous and smooth but near
// the points of j's edge nearest to it, where its derivative has a logarithm of the distance:
// halved there until two levels agree, which a near pair reaches in a few dozen halvings
// rather than the quadtree over the area that Lambert's form needs.
#include "formfactor/contour_factors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::formfactor {

namespace {

// ∫_{s1}^{s2} ln √(s² + h²) ds, h ≥ 0 the distance of the point from the edge's line and s along
// the line from the foot of the perpendicular (atan2 makes h = 0 the limit s ln|s| − s).
double logLineIntegral(double s1, double s2, double h) {
  const auto primitive = [h](double s) {
    const double r2 = s * s + h * h;
    return (r2 > 0 ? 0.5 * s * std::log(r2) : 0.0) - s + h * std::atan2(s, h);
  };
  return primitive(s2) - primitive(s1);
}

struct Edge {
  Vec3 from;
  Vec3 along;  ///< unit
  double length;
};

// ∫ ln |x − y| dy over the edge.
double logEdgeIntegral(Vec3 x, const Edge& e) {
  const Vec3 d = x - e.from;
  const double t = dot(d, e.along);
  const double h = length(cross(d, e.along));  // (not √(|d|² − t²): no cancellation near the line)
  return logLineIntegral(-t, e.length - t, h);
}

// Gauss-Legendre, 8 points on [-1, 1] (exact to degree 15): the positive half.
constexpr double kNode[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                             0.9602898564975363};
constexpr double kWeight[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                               0.1012285362903763};

struct Piece {
  double value;
  double magnitude;  ///< of |integrand|: the scale of the round-off in value
};

// ∫ over s in [a, b] of f(e.from + s e.along) for f = logEdgeIntegral(·, g).
Piece gaussPiece(const Edge& e, const Edge& g, double a, double b) {
  const double middle = 0.5 * (a + b), half = 0.5 * (b - a);
  double value = 0, magnitude = 0;
  for (int k = 0; k < 4; ++k) {
    for (double side : {-1.0, 1.0}) {
      const double f = logEdgeIntegral(e.from + (middle + side * half * kNode[k]) * e.along, g);
      value += kWeight[k] * f;
      magnitude += kWeight[k] * std::abs(f);
    }
  }
  return {half * value, half * magnitude};
}

// Below this share of the integrand's magnitude two levels' difference is round-off.
constexpr double kRoundOff = 1e-14;

// The parameters [a, b] along e and gaussPiece's estimate over them.
struct Span {
  double a, b;
  Piece whole;
};

// `span`'s estimate refined until its halves agree with it to `tolerance`; the differences of
// the pieces accepted added to `error`.
double adaptive(const Edge& e, const Edge& g, Span span, double tolerance, int depth,
                double& error) {
  const auto [a, b, whole] = span;
  const double middle = 0.5 * (a + b);
  const Piece left = gaussPiece(e, g, a, middle), right = gaussPiece(e, g, middle, b);
  const double fine = left.value + right.value, difference = std::abs(fine - whole.value);
  if (difference <= std::max(tolerance, kRoundOff * whole.magnitude) || depth >= kContourMaxDepth) {
    error += difference;
    return fine;
  }
  return adaptive(e, g, {a, middle, left}, tolerance / 2, depth + 1, error) +
         adaptive(e, g, {middle, b, right}, tolerance / 2, depth + 1, error);
}

// The edges of t counter-clockwise about `normal`, in the frame (x − origin) / scale.
std::array<Edge, 3> edgesOf(const PatchShape& t, Vec3 origin, double scale) {
  std::array<Vec3, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = (1 / scale) * (t.corners[k] - origin);
  if (dot(cross(c[1] - c[0], c[2] - c[0]), t.normal) < 0) std::swap(c[1], c[2]);
  std::array<Edge, 3> edges;
  for (int k = 0; k < 3; ++k) {
    const Vec3 span = c[(k + 1) % 3] - c[k];
    edges[k] = {c[k], normalize(span), length(span)};
  }
  return edges;
}

}  // namespace

ContourFactor contourFactor(const PatchShape& i, const PatchShape& j) {
  const double scale = i.radius + j.radius + length(j.centroid - i.centroid);
  const std::array<Edge, 3> from = edgesOf(i, i.centroid, scale),
                            to = edgesOf(j, i.centroid, scale);
  const double twiceArea = length(cross(from[1].from - from[0].from, from[2].from - from[0].from));
  const double toFactor = 1 / (std::numbers::pi * twiceArea);  // 1/(2π A_i), in the frame
  double sum = 0, error = 0;
  for (const Edge& e : from) {
    for (const Edge& g : to) {
      const double cosine = dot(e.along, g.along);
      if (cosine == 0) continue;
      // Each of the nine to a ninth of the tolerance, in units of the sum.
      const double tolerance = kContourTolerance / (9 * toFactor * std::abs(cosine));
      double edgeError = 0;
      const Piece whole = gaussPiece(e, g, 0, e.length);
      sum += cosine * adaptive(e, g, {0, e.length, whole}, tolerance, 0, edgeError);
      // (and the round-off of a term this size: the terms cancel to A_i F_ij, much less where i
      // is small beside j)
      error += std::abs(cosine) * (edgeError + kRoundOff * whole.magnitude);
    }
  }
  return {std::max(0.0, sum * toFactor), error * toFactor};
}

}  // namespace radiosity::formfactor
