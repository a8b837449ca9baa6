// An 8-bit RGB picture being drawn (the false-colour map and its legend). Private to render/.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace radiosity::render {

using Colour = std::array<uint8_t, 3>;  ///< sRGB-encoded bytes

struct Canvas {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< height rows of width×3 bytes, top row first

  Canvas(int w, int h, Colour background) : width(w), height(h) {
    rgb.reserve(static_cast<size_t>(w) * h * 3);
    for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p)
      rgb.insert(rgb.end(), background.begin(), background.end());
  }

  /// Sets pixel (x, y), (0, 0) the top-left corner; a pixel outside is left alone (text that
  /// does not fit is cut, not a crash).
  void set(int x, int y, Colour colour) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    uint8_t* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
    for (int c = 0; c < 3; ++c) p[c] = colour[c];
  }

  void fill(int x0, int y0, int w, int h, Colour colour) {
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) set(x, y, colour);
  }
};

}  // namespace radiosity::render
