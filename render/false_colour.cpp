#include "render/false_colour.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/bitmap_font.h"
#include "render/colour_scale.h"

namespace radiosity::render {

namespace {

constexpr int kLegendLines = 3;      // quantity, unit, scale
constexpr int kLabelCells = 14;      // the widest line of text the legend leaves room for
constexpr int kShortestBar = 64;     // font pixels
constexpr int kTextScaleFrom = 384;  // picture height from which the text is drawn twice as big

// The colour bar, bottom to top, its ticks and their labels (a label too close to the one below
// it is left out; its tick stays).
void drawBar(Canvas& canvas, const LegendLayout& at, const ColourScale& scale) {
  const int s = at.textScale;
  const int bottom = at.barY + at.barHeight - 1;
  for (int row = 0; row < at.barHeight; ++row)
    canvas.fill(at.barX, bottom - row, at.barWidth, 1,
                colourAt(static_cast<double>(row) / (at.barHeight - 1)));
  int lastLabel = -1;
  for (double tick : scale.ticks) {
    const int y = bottom - static_cast<int>(std::lround(scale.position(tick) * (at.barHeight - 1)));
    canvas.fill(at.barX + at.barWidth, y, 3 * s, s, kInk);
    const int labelTop = y - (kGlyphHeight / 2) * s;
    if (lastLabel >= 0 && lastLabel - labelTop < kCellHeight * s) continue;
    drawText(canvas, at.barX + at.barWidth + 5 * s, labelTop, tickLabel(tick), s, kInk);
    lastLabel = labelTop;
  }
}

}  // namespace

LegendLayout legendLayout(int pictureWidth, int pictureHeight) {
  LegendLayout at;
  const int s = at.textScale = pictureHeight >= kTextScaleFrom ? 2 : 1;
  const int margin = 8 * s;
  at.textX = pictureWidth + margin;
  at.textY = margin;
  at.width = pictureWidth + margin + kLabelCells * kCellWidth * s + margin;
  // A blank line under the text leaves room for the top tick's label.
  at.barX = at.textX;
  at.barY = at.textY + (kLegendLines + 1) * kCellHeight * s;
  at.barWidth = 12 * s;
  const int belowBar = margin + kGlyphHeight * s;  // the bottom tick's label hangs below the bar
  at.height = std::max(pictureHeight, at.barY + kShortestBar * s + belowBar);
  at.barHeight = at.height - at.barY - belowBar;
  return at;
}

Canvas falseColourMap(const std::vector<double>& values, int width, int height,
                      const LegendText& text, Scale scaleChoice, bool range) {
  double smallestPositive = 0, largest = 0;
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  for (double v : values) {
    if (std::isnan(v)) continue;
    largest = std::max(largest, v);
    lowest = std::min(lowest, v);
    highest = std::max(highest, v);
    if (v > 0 && (smallestPositive == 0 || v < smallestPositive)) smallestPositive = v;
  }
  const ColourScale scale = range && scaleChoice != Scale::kLog
                                ? rangeScale(lowest, highest)
                                : chooseScale(smallestPositive, largest, scaleChoice);

  const LegendLayout at = legendLayout(width, height);
  Canvas canvas(at.width, at.height, kBackground);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double v = values[static_cast<size_t>(y) * width + x];
      if (!std::isnan(v)) canvas.set(x, y, colourAt(scale.position(v)));
    }
  }
  const int s = at.textScale, line = kCellHeight * s;
  drawText(canvas, at.textX, at.textY, text.quantity, s, kInk);
  drawText(canvas, at.textX, at.textY + line, text.unit, s, kInk);
  drawText(canvas, at.textX, at.textY + 2 * line, scale.log ? "log scale" : "linear scale", s,
           kInk);
  drawBar(canvas, at, scale);
  return canvas;
}

}  // namespace radiosity::render
