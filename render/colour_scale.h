// How a false-colour map turns values into colours: a linear or log scale whose range and ticks
// are chosen from the values shown, and a perceptually uniform colour map (viridis). Private to
// render/ (and its tests).
#pragma once

#include <string>
#include <vector>

#include "render/canvas.h"
#include "render/render.h"

namespace radiosity::render {

struct ColourScale {
  bool log = false;
  double low = 0, high = 1;   ///< the values at the bar's bottom and top (low < high)
  std::vector<double> ticks;  ///< the values labelled on the bar, from low to high

  /// Where `value` lies on the bar: 0 at low, 1 at high, clamped to [0, 1] (on a log scale a
  /// value ≤ 0 is at 0; NaN is at 0).
  double position(double value) const;
};

/// The scale for values whose smallest positive one is `smallestPositive` (0: none) and whose
/// largest is `largest`. Linear: from 0 to a round number at or above `largest`, 3 to 6 ticks.
/// Log: whole decades around [smallestPositive, largest], at most kMaxDecades of them, a tick a
/// decade (and at 2 and 5 where there are at most two decades). kAuto is log where
/// largest / smallestPositive exceeds kAutoLogRatio.
ColourScale chooseScale(double smallestPositive, double largest, Scale scale);

/// A linear scale over [lowest, largest], which may be negative (a net flux), from a round
/// number at or below `lowest` to one at or above `largest`, 3 to 6 ticks a round step apart.
ColourScale rangeScale(double lowest, double largest);

inline constexpr double kAutoLogRatio = 100;  ///< two decades
inline constexpr int kMaxDecades = 6;

/// The colour map at `position` in [0, 1] (clamped): viridis, dark violet to yellow, whose
/// lightness rises steadily, so that equal steps of value look like equal steps of colour and
/// the map reads in grey too.
Colour colourAt(double position);

/// A tick's label: the value in at most four significant digits (%.4g: 0.25, 1500, 1e+05).
std::string tickLabel(double value);

}  // namespace radiosity::render
