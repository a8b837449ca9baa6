// Closed-form view factors between rectangles (Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors", C-11 and C-14; parallel rectangles anywhere in their planes from Ehlert
// and Smith, J. Thermophysics and Heat Transfer 7, 1993), the exact answers the sampled form
// factors must meet.
#pragma once

#include <cmath>
#include <numbers>

namespace radiosity::testing {

/// From an a×b rectangle to an identical, directly opposite, parallel one at distance c.
inline double parallelRectangles(double a, double b, double c) {
  const double X = a / c, Y = b / c;
  const double x2 = 1 + X * X, y2 = 1 + Y * Y;
  return 2.0 / (std::numbers::pi * X * Y) *
         (std::log(std::sqrt(x2 * y2 / (x2 + Y * Y))) +
          X * std::sqrt(y2) * std::atan(X / std::sqrt(y2)) +
          Y * std::sqrt(x2) * std::atan(Y / std::sqrt(x2)) - X * std::atan(X) - Y * std::atan(Y));
}

/// From a rectangle of width w (along the common edge l) and height h, to the perpendicular
/// rectangle l×w2 sharing the edge of length l: H = h/l, W = w2/l (Howell C-14, from the
/// h-rectangle to the w2-rectangle).
inline double perpendicularRectangles(double l, double h, double w2) {
  const double H = h / l, W = w2 / l;
  const double H2 = H * H, W2 = W * W, S = std::sqrt(H2 + W2);
  const double term1 = W * std::atan(1 / W) + H * std::atan(1 / H) - S * std::atan(1 / S);
  const double a = (1 + W2) * (1 + H2) / (1 + W2 + H2);
  const double b = W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2));
  const double c = H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2));
  const double term2 = 0.25 * std::log(a * std::pow(b, W2) * std::pow(c, H2));
  return (term1 + term2) / (std::numbers::pi * H);
}

/// An axis-aligned rectangle [x0, x1] × [y0, y1] in a plane of constant z.
struct Rectangle {
  double x0, x1, y0, y1;
};

/// From rectangle r at z = 0 to the parallel rectangle s at z = c, wherever each lies in its
/// plane: the corner-to-corner function G summed over the 16 pairs of corners with alternating
/// signs.
inline double parallelRectangles(Rectangle r, Rectangle s, double c) {
  auto g = [c](double x, double y) {
    const double sx = std::sqrt(x * x + c * c), sy = std::sqrt(y * y + c * c);
    return (x * sy * std::atan(x / sy) + y * sx * std::atan(y / sx) -
            c * c / 2 * std::log(x * x + y * y + c * c)) /
           (2 * std::numbers::pi);
  };
  double sum = 0;
  for (int corner = 0; corner < 16; ++corner) {
    const int i = corner & 1, j = corner >> 1 & 1, k = corner >> 2 & 1, l = corner >> 3 & 1;
    const double x = (k ? s.x1 : s.x0) - (i ? r.x1 : r.x0);
    const double y = (l ? s.y1 : s.y0) - (j ? r.y1 : r.y0);
    sum += ((i + j + k + l) & 1 ? -1 : 1) * g(x, y);
  }
  return sum / ((r.x1 - r.x0) * (r.y1 - r.y0));
}

/// From rectangle r, in the plane z = 0 over x ∈ [r.x0, r.x1] and y ∈ [r.y0, r.y1] (y ≥ 0),
/// to rectangle s in the plane y = 0 over x ∈ [s.x0, s.x1] and z ∈ [s.y0, s.y1] (z ≥ 0): two
/// perpendicular rectangles anywhere along their common line x, facing each other. The
/// corner-to-corner function summed over the 16 pairs of corners (Ehlert and Smith 1993).
inline double perpendicularRectangles(Rectangle r, Rectangle s) {
  auto g = [](double u, double w2) {  // w2 = y² + z²
    const double w = std::sqrt(w2), l = u * u + w2;
    return (w > 0 ? u * w * std::atan(u / w) : 0.0) +
           (l > 0 ? 0.25 * (u * u - w2) * std::log(l) : 0.0);
  };
  double sum = 0;
  for (int corner = 0; corner < 16; ++corner) {
    const int i = corner & 1, j = corner >> 1 & 1, k = corner >> 2 & 1, l = corner >> 3 & 1;
    const double x = i ? r.x1 : r.x0, y = j ? r.y1 : r.y0;
    const double z = k ? s.y1 : s.y0, xi = l ? s.x1 : s.x0;
    sum += ((i + j + k + l) & 1 ? -1 : 1) * g(x - xi, y * y + z * z);
  }
  return sum / (2 * std::numbers::pi * (r.x1 - r.x0) * (r.y1 - r.y0));
}

}  // namespace radiosity::testing
