// A PFM that `radiosity render` wrote, read back for the tests: its header as written and its
// pixels, top row first (the file holds them bottom row first).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity::testing {

struct FloatPicture {
  int width = 0, height = 0;
  std::string header;      ///< the three header lines, newlines included
  size_t fileSize = 0;     ///< bytes
  std::vector<float> rgb;  ///< top row first
  std::array<float, 3> at(int x, int y) const {
    const float* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
};

/// Reads a little-endian colour PFM ("PF", scale -1.0); fails the test for anything else.
inline FloatPicture readPfm(const std::filesystem::path& path) {
  FloatPicture picture;
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  picture.fileSize = bytes.size();
  // Three lines: "PF", "<width> <height>", "<scale>".
  size_t end = 0;
  for (int line = 0; line < 3; ++line) {
    end = bytes.find('\n', end);
    if (end == std::string::npos) {
      ADD_FAILURE() << path << ": no PFM header";
      return picture;
    }
    ++end;
  }
  picture.header = bytes.substr(0, end);
  std::istringstream header(picture.header);
  std::string magic, scale;
  header >> magic >> picture.width >> picture.height >> scale;
  EXPECT_EQ(magic, "PF") << path << " is not a colour PFM";
  EXPECT_EQ(scale, "-1.0") << path << ": not little-endian with scale 1";
  const size_t values = static_cast<size_t>(picture.width) * picture.height * 3;
  if (bytes.size() != end + 4 * values) {
    ADD_FAILURE() << path << ": " << bytes.size() - end << " bytes of pixels, not " << 4 * values;
    return picture;
  }
  picture.rgb.resize(values);
  const size_t rowValues = static_cast<size_t>(picture.width) * 3;
  for (size_t i = 0; i < values; ++i) {
    uint32_t bits = 0;
    for (int b = 0; b < 4; ++b)
      bits |= uint32_t{static_cast<unsigned char>(bytes[end + 4 * i + b])} << (8 * b);
    const size_t fileRow = i / rowValues, topRow = picture.height - 1 - fileRow;
    picture.rgb[topRow * rowValues + i % rowValues] = std::bit_cast<float>(bits);
  }
  return picture;
}

}  // namespace radiosity::testing
