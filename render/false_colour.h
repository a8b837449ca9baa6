// A false-colour map: each pixel's value through the colour scale (render/colour_scale.h), and
// beside the picture a legend: what is shown, its unit, the scale, and a colour bar with tick
// labels. Private to render/ (and its tests).
#pragma once

#include <string>
#include <vector>

#include "render/canvas.h"
#include "render/render.h"

namespace radiosity::render {

/// Where the legend goes, for a picture of the given size: it is drawn to the picture's right,
/// and the canvas is made taller than the picture where the legend needs the room.
struct LegendLayout {
  int width = 0, height = 0;  ///< the whole canvas
  int textScale = 1;          ///< pixels per font pixel: 2 for pictures 384 pixels high or more
  int textX = 0, textY = 0;   ///< the top-left corner of the legend's first line of text
  int barX = 0, barY = 0;     ///< the colour bar's top-left corner; its top row is the scale's top
  int barWidth = 0, barHeight = 0;
};

LegendLayout legendLayout(int pictureWidth, int pictureHeight);

/// What the legend says above the bar.
struct LegendText {
  std::string quantity;  ///< "radiosity B"
  std::string unit;      ///< "W/m^2"
};

inline constexpr Colour kBackground = {0, 0, 0};  ///< where no surface is seen, and the legend's
inline constexpr Colour kInk = {230, 230, 230};   ///< the legend's text and ticks

/// The map of `values` (width × height, top row first; NaN where no surface is seen, drawn as
/// background) on the scale `scale` chooses for them, with its legend. The scale's range comes
/// from the values themselves (chooseScale), so it depends on the picture, not on how it was
/// computed. `range`: a linear scale over the values' own range (rangeScale: a temperature, a
/// net flux that changes sign) instead of chooseScale's, unless `scale` is kLog.
Canvas falseColourMap(const std::vector<double>& values, int width, int height,
                      const LegendText& text, Scale scale, bool range = false);

}  // namespace radiosity::render
