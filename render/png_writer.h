// The libpng adapter of render/: 8-bit RGB pictures, written atomically. Private to render/.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace radiosity::render {

/// Writes `rgb` (height rows of width×3 bytes, top row first) as an 8-bit RGB PNG. The file
/// appears under `path` only when complete (written beside it under a temporary name, then
/// renamed); on failure nothing is left, an existing `path` is unchanged, and
/// Error(kFailure) names the file and the cause. Serial.
void writePngRgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace radiosity::render
