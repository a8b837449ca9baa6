// What one setting of `radiosity study` measured, as the CSV, the log and the plot take it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/vec3.h"
#include "formfactor/estimator.h"
#include "solve/solve.h"

namespace radiosity::jobs {

/// Errors per channel in the measure of measure/light_error.h (RMS over the reflecting patches of
/// each patch's error relative to its reference value, floored at 1 % of the mean), the largest
/// such relative error, and the share of reflecting patches whose error is within twice the
/// estimated standard error (when there is one).
struct ChannelErrors {
  Rgb rms{0, 0, 0}, largest{0, 0, 0}, covered{0, 0, 0};
};

/// One setting of the sweep (a mesh, an estimator, rays and a tolerance) and what it measured.
struct SettingResult {
  formfactor::Estimator estimator = formfactor::Estimator::kHemisphere;
  int64_t rays = 0;
  double rtol = 0;
  solve::Report report;
  ChannelErrors b, h;  ///< of B and of H
  double formFactorSeconds = 0, solveSeconds = 0;
  double seconds = 0;  ///< mesh + form factors + solve
};

/// The largest channel.
inline double worst(const Rgb& v) { return std::max({v[0], v[1], v[2]}); }

/// The short form of a number in the CSV, the log and the plot (%.6g).
inline std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

}  // namespace radiosity::jobs
