#include "render/colour_scale.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace radiosity::render {

namespace {

// matplotlib's viridis at 17 evenly spaced points (sRGB-encoded, 0–1); linear interpolation
// between them is within 5 levels (of 255) of its 256-entry table, and keeps the lightness rising.
constexpr std::array<std::array<double, 3>, 17> kViridis = {{
    {0.267004, 0.004874, 0.329415},
    {0.282327, 0.094955, 0.417331},
    {0.278826, 0.175490, 0.483397},
    {0.258965, 0.251537, 0.524736},
    {0.229739, 0.322361, 0.545706},
    {0.199430, 0.387607, 0.554642},
    {0.172719, 0.448791, 0.557885},
    {0.149039, 0.508051, 0.557250},
    {0.127568, 0.566949, 0.550556},
    {0.120638, 0.625828, 0.533488},
    {0.157851, 0.683765, 0.501686},
    {0.246070, 0.738910, 0.452024},
    {0.369214, 0.788888, 0.382914},
    {0.515992, 0.831158, 0.294279},
    {0.678489, 0.863742, 0.189503},
    {0.845561, 0.887322, 0.099702},
    {0.993248, 0.906157, 0.143936},
}};

// A step of 1, 2, 2.5 or 5 times a power of ten that splits [0, largest] into at most 5.
double roundStep(double largest) {
  const double raw = largest / 5;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 2.5, 5.0})
    if (raw <= factor * magnitude * (1 + 1e-12)) return factor * magnitude;
  return 10 * magnitude;
}

ColourScale linearScale(double largest) {
  ColourScale scale;
  const double step = roundStep(largest);
  const int intervals = std::max(2, static_cast<int>(std::ceil(largest / step * (1 - 1e-12))));
  for (int k = 0; k <= intervals; ++k) scale.ticks.push_back(k * step);
  scale.high = scale.ticks.back();
  return scale;
}

ColourScale logScale(double smallestPositive, double largest) {
  ColourScale scale;
  scale.log = true;
  int top = static_cast<int>(std::ceil(std::log10(largest) - 1e-12));
  int bottom = static_cast<int>(std::floor(std::log10(smallestPositive) + 1e-12));
  bottom = std::clamp(bottom, top - kMaxDecades, top - 1);
  scale.low = std::pow(10.0, bottom);
  scale.high = std::pow(10.0, top);
  const bool fine = top - bottom <= 2;
  for (int decade = bottom; decade <= top; ++decade) {
    scale.ticks.push_back(std::pow(10.0, decade));
    if (fine && decade < top)
      for (double factor : {2.0, 5.0}) scale.ticks.push_back(factor * std::pow(10.0, decade));
  }
  std::sort(scale.ticks.begin(), scale.ticks.end());
  return scale;
}

}  // namespace

double ColourScale::position(double value) const {
  double t = 0;
  if (log)
    t = value > 0 ? (std::log10(value) - std::log10(low)) / (std::log10(high) - std::log10(low))
                  : 0;
  else
    t = (value - low) / (high - low);
  return std::isnan(t) ? 0 : std::clamp(t, 0.0, 1.0);
}

ColourScale rangeScale(double lowest, double largest) {
  if (!std::isfinite(lowest) || !std::isfinite(largest) || lowest > largest) lowest = largest = 0;
  double span = largest - lowest;
  if (!(span > 0)) span = std::max(std::abs(largest), 1.0);
  const double step = roundStep(span);
  const double bottom = std::floor(lowest / step * (1 + 1e-12)) * step;
  int intervals = std::max(2, static_cast<int>(std::ceil((largest - bottom) / step * (1 - 1e-12))));
  ColourScale scale;
  for (int k = 0; k <= intervals; ++k) scale.ticks.push_back(bottom + k * step);
  scale.low = scale.ticks.front();
  scale.high = scale.ticks.back();
  return scale;
}

ColourScale chooseScale(double smallestPositive, double largest, Scale scale) {
  // Nothing lit (or nothing seen): a unit scale, on which every value is at the bottom.
  if (!(largest > 0) || !std::isfinite(largest)) largest = 1;
  if (!(smallestPositive > 0) || smallestPositive > largest) smallestPositive = largest;
  const bool log =
      scale == Scale::kLog || (scale == Scale::kAuto && largest > kAutoLogRatio * smallestPositive);
  return log ? logScale(smallestPositive, largest) : linearScale(largest);
}

Colour colourAt(double position) {
  const double t = std::clamp(std::isnan(position) ? 0.0 : position, 0.0, 1.0);
  const double at = t * (kViridis.size() - 1);
  const size_t below = std::min(static_cast<size_t>(at), kViridis.size() - 2);
  const double f = at - below;
  Colour colour;
  for (int c = 0; c < 3; ++c) {
    const double value = (1 - f) * kViridis[below][c] + f * kViridis[below + 1][c];
    colour[c] = static_cast<uint8_t>(std::lround(255 * value));
  }
  return colour;
}

std::string tickLabel(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

}  // namespace radiosity::render
