// A 5×7 pixel font for the legend of a false-colour map: digits, the letters, and the signs of
// numbers and units (. - + e / ^ ( ) , : = %). Private to render/.
#pragma once

#include <string>

#include "render/canvas.h"

namespace radiosity::render {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
/// A character's cell: the glyph and a column and two rows of space.
inline constexpr int kCellWidth = 6, kCellHeight = 9;

/// The width in pixels of `text` drawn at `scale` (pixels per font pixel).
int textWidth(const std::string& text, int scale);

/// Draws `text` with its cell's top-left corner at (x, y), each font pixel a scale×scale block.
/// A character the font lacks is drawn as a hollow box, so that it shows rather than vanishes.
void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale, Colour colour);

}  // namespace radiosity::render
