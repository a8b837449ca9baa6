// A PNG that `radiosity render` wrote, read back with libpng for the tests to look at its pixels.
#pragma once

#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

namespace radiosity::testing {

struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::array<int, 3> at(int x, int y) const {
    const uint8_t* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  int sum(int x, int y) const {
    auto p = at(x, y);
    return p[0] + p[1] + p[2];
  }
};

/// Reads an 8-bit RGB PNG; fails the test for anything else.
inline Picture readPng(const std::filesystem::path& path) {
  Picture picture;
  std::ifstream in(path, std::ios::binary);
  unsigned char signature[8] = {};
  in.read(reinterpret_cast<char*>(signature), 8);
  EXPECT_EQ(png_sig_cmp(signature, 0, 8), 0) << path << " is not a PNG";
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    ADD_FAILURE() << "libpng cannot read " << path << ": " << image.message;
    return picture;
  }
  EXPECT_EQ(image.format, static_cast<png_uint_32>(PNG_FORMAT_RGB)) << "not 8-bit RGB";
  image.format = PNG_FORMAT_RGB;
  picture.width = static_cast<int>(image.width);
  picture.height = static_cast<int>(image.height);
  picture.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, picture.rgb.data(), 0, nullptr))
    ADD_FAILURE() << "libpng cannot decode " << path << ": " << image.message;
  return picture;
}

}  // namespace radiosity::testing
