// Closed-form view factors between rectangles (Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors", C-11 and C-14), the exact answers the sampled form factors must meet.
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

}  // namespace radiosity::testing
