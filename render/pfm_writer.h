// The PFM writer of render/: linear float RGB pictures (Netpbm's Portable Float Map), written
// atomically. Private to render/.
#pragma once

#include <string>
#include <vector>

namespace radiosity::render {

/// Writes `rgb` (height rows of width×3 floats, top row first) as a colour PFM: the header
/// "PF\n<width> <height>\n-1.0\n" (a negative scale: little-endian floats), then the rows
/// bottom to top, as the format has them. The file appears under `path` only when complete (a
/// temporary beside it, renamed); on failure nothing is left, an existing `path` is unchanged,
/// and Error(kFailure) names the file and the cause. Serial.
void writePfmRgb(const std::string& path, int width, int height, const std::vector<float>& rgb);

}  // namespace radiosity::render
