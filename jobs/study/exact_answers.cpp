// Exact answers of the built-in scenes that have one (see exact_answers.h).
#include "jobs/study/exact_answers.h"
#include "io/scene/scene.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <string_view>

namespace radiosity::jobs {
namespace {

/// The value every patch has in `values`, or nullopt if they differ (or there are none).
std::optional<Rgb> uniform(const std::vector<Rgb>& values) {
  if (values.empty()) return std::nullopt;
  for (const Rgb& v : values) {
    if (v != values.front()) return std::nullopt;
  }
  return values.front();
}

bool anyChannelAtLeastOne(const Rgb& rho) { return rho[0] >= 1 || rho[1] >= 1 || rho[2] >= 1; }

std::optional<ExactAnswer> closedBox(const Mesh& patches) {
  const auto rho = uniform(patches.reflectance), e = uniform(patches.emission);
  if (!rho || !e || anyChannelAtLeastOne(*rho)) return std::nullopt;
  Rgb b;
  for (int c = 0; c < 3; ++c) b[c] = (*e)[c] / (1 - (*rho)[c]);
  const size_t n = patches.triangles.size();
  return ExactAnswer{std::vector<Rgb>(n, b), std::vector<Rgb>(n, b),
                     "closed box, uniform rho and E: B = E/(1 - rho), H = B"};
}

std::optional<ExactAnswer> closedSphere(const Mesh& patches) {
  const auto rho = uniform(patches.reflectance);
  if (!rho || anyChannelAtLeastOne(*rho) || patches.triangles.empty()) return std::nullopt;
  Rgb weighted = {0, 0, 0};
  double total = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const double a = patches.area(t);
    total += a;
    for (int c = 0; c < 3; ++c) weighted[c] += a * patches.emission[t][c];
  }
  Rgb h;
  for (int c = 0; c < 3; ++c) h[c] = weighted[c] / total / (1 - (*rho)[c]);
  ExactAnswer answer;
  answer.irradiance.assign(patches.triangles.size(), h);
  answer.radiosity.resize(patches.triangles.size());
  for (size_t t = 0; t < patches.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) answer.radiosity[t][c] = patches.emission[t][c] + (*rho)[c] * h[c];
  }
  answer.how =
      "closed sphere, uniform rho: F_ij = A_j/A, Ebar = sum_j A_j E_j / A, H = Ebar/(1 - rho), "
      "B = E + rho H (exact for a sphere; for the faceted icosphere exact up to faceting)";
  return answer;
}

constexpr double kInvTwoPi = 0.5 / std::numbers::pi;

/// From a differential element at height c > 0 above a plane, facing it, to the rectangle
/// [0, u] × [0, v] of that plane whose corner (0, 0) lies under the element (Howell's
/// catalogue: plane element to a parallel rectangle, normal through a corner). Odd in u and in
/// v, so that signed sides give the signed sub-rectangles of any rectangle.
double parallelCorner(double u, double v, double c) {
  const double a = u / c, b = v / c;
  const double sa = std::sqrt(1 + a * a), sb = std::sqrt(1 + b * b);
  return kInvTwoPi * (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb));
}

/// From a differential element at distance c ≥ 0 from the line where its plane meets a
/// perpendicular one, facing it, to the rectangle [0, u] along that line × [0, depth] away from
/// it in the other plane, with the corner (0, 0) the foot of the element on the line (Howell's
/// catalogue: plane element to a rectangle in a plane at 90°, corner on the common line). Odd
/// in u.
double perpendicularCorner(double u, double depth, double c) {
  const double s = std::sqrt(depth * depth + c * c);
  return kInvTwoPi * (std::atan2(u, c) - c / s * std::atan(u / s));
}

/// The 16-point degree-8 rule on a triangle (Dunavant 1985): barycentric coordinates, weight.
struct QuadraturePoint {
  double l0, l1, l2, weight;
};

const std::vector<QuadraturePoint>& dunavant8() {
  static const std::vector<QuadraturePoint> rule = [] {
    std::vector<QuadraturePoint> points = {{1.0 / 3, 1.0 / 3, 1.0 / 3, 0.144315607677787}};
    const std::array<std::array<double, 2>, 3> threes = {{{0.459292588292723, 0.095091634267285},
                                                          {0.170569307751760, 0.103217370534718},
                                                          {0.050547228317031, 0.032458497623198}}};
    for (const auto& [a, w] : threes) {
      const double b = 1 - 2 * a;
      points.push_back({b, a, a, w});
      points.push_back({a, b, a, w});
      points.push_back({a, a, b, w});
    }
    const double p = 0.008394777409958, q = 0.263112829634638, r = 1 - p - q;
    const double w = 0.027230314174435;
    for (const auto& [x, y, z] : std::array<std::array<double, 3>, 6>{
             {{p, q, r}, {p, r, q}, {q, p, r}, {q, r, p}, {r, p, q}, {r, q, p}}}) {
      points.push_back({x, y, z, w});
    }
    return points;
  }();
  return rule;
}

double ruleMean(const std::function<double(const Vec3&)>& f, Vec3 a, Vec3 b, Vec3 c) {
  double sum = 0;
  for (const QuadraturePoint& q : dunavant8()) sum += q.weight * f(q.l0 * a + q.l1 * b + q.l2 * c);
  return sum;
}

double adaptiveMean(const std::function<double(const Vec3&)>& f, Vec3 a, Vec3 b, Vec3 c,
                    double coarse, double tolerance, int depthLeft) {
  const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const std::array<std::array<Vec3, 3>, 4> children = {
      {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}};
  std::array<double, 4> means;
  for (int k = 0; k < 4; ++k) {
    means[k] = ruleMean(f, children[k][0], children[k][1], children[k][2]);
  }
  const double fine = 0.25 * (means[0] + means[1] + means[2] + means[3]);
  if (depthLeft <= 1 || std::abs(fine - coarse) <= tolerance) return fine;
  double sum = 0;
  for (int k = 0; k < 4; ++k) {
    sum += adaptiveMean(f, children[k][0], children[k][1], children[k][2], means[k], tolerance,
                        depthLeft - 1);
  }
  return 0.25 * sum;
}

/// Quadrature error allowed on each receiver patch's view factor (well below the 1e-6 asked).
constexpr double kViewFactorTolerance = 1e-10;

std::optional<ExactAnswer> plates(const BuiltinSpec& spec, const Mesh& patches) {
  // The receiver may reflect: its light goes to a black emitter or escapes, never back. A
  // reflecting emitter would return it: no closed form.
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const Rgb& rho = patches.reflectance[t];
    if (patches.sourceFace[t] == 0 && (rho[0] > 0 || rho[1] > 0 || rho[2] > 0)) return std::nullopt;
  }
  const double w = spec.parameters.at("width"), h = spec.parameters.at("height");
  const double angle = spec.parameters.at("angle");
  const int64_t n = patches.triangleCount();
  if (patches.sourceFace.size() != static_cast<size_t>(n)) return std::nullopt;
  // Source face 0 is the emitter (z = 0), 1 the receiver; the receiver must not emit.
  std::optional<Rgb> e;
  for (int64_t t = 0; t < n; ++t) {
    const Rgb& et = patches.emission[t];
    if (patches.sourceFace[t] == 0) {
      if (e && *e != et) return std::nullopt;
      e = et;
    } else if (et != Rgb{0, 0, 0}) {
      return std::nullopt;
    }
  }
  const Rgb emitted = e.value_or(Rgb{0, 0, 0});

  // The view factor from a point of the receiver (facing the emitter) to the emitter
  // [0, w] × [0, h] × {0}.
  std::function<double(const Vec3&)> pointFactor;
  std::string how;
  if (angle == 0) {
    pointFactor = [w, h](const Vec3& p) {
      const double c = p.z, x0 = -p.x, x1 = w - p.x, y0 = -p.y, y1 = h - p.y;
      return parallelCorner(x1, y1, c) - parallelCorner(x0, y1, c) - parallelCorner(x1, y0, c) +
             parallelCorner(x0, y0, c);
    };
    how =
        "parallel plates, black emitter: H = E F(patch -> emitter) and B = rho H on the receiver "
        "(the emitter's H is not compared), F by adaptive Dunavant quadrature of the exact "
        "point-to-parallel-rectangle "
        "view factor";
  } else {
    pointFactor = [w, h](const Vec3& p) {
      return perpendicularCorner(w - p.x, h, p.z) - perpendicularCorner(-p.x, h, p.z);
    };
    how =
        "perpendicular plates, black emitter: H = E F(patch -> emitter) and B = rho H on the "
        "receiver (the emitter's H is not compared), F by adaptive Dunavant quadrature of the "
        "exact point-to-perpendicular-"
        "rectangle view factor";
  }

  ExactAnswer answer;
  answer.radiosity = patches.emission;
  answer.irradiance.assign(n, Rgb{0, 0, 0});
  for (int64_t t = 0; t < n; ++t) {
    if (patches.sourceFace[t] == 0) continue;
    const double f = meanOverTriangle(pointFactor, patches.corner(t, 0), patches.corner(t, 1),
                                      patches.corner(t, 2), kViewFactorTolerance);
    for (int c = 0; c < 3; ++c) {
      answer.irradiance[t][c] = emitted[c] * f;
      answer.radiosity[t][c] += patches.reflectance[t][c] * answer.irradiance[t][c];
    }
  }
  answer.how = how;
  return answer;
}

}  // namespace

double meanOverTriangle(const std::function<double(const Vec3&)>& f, Vec3 a, Vec3 b, Vec3 c,
                        double tolerance, int maxDepth) {
  const double coarse = ruleMean(f, a, b, c);
  if (maxDepth <= 0) return coarse;
  return adaptiveMean(f, a, b, c, coarse, tolerance, maxDepth);
}

std::optional<ExactAnswer> exactAnswer(const std::string& scene, const Mesh& patches) {
  const std::optional<BuiltinSpec> spec = parseBuiltinSpec(scene);
  if (!spec) return std::nullopt;
  if (spec->name == "box") return closedBox(patches);
  if (spec->name == "sphere") return closedSphere(patches);
  if (spec->name == "plates") return plates(*spec, patches);
  return std::nullopt;
}

}  // namespace radiosity::jobs
