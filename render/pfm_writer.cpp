#include "render/pfm_writer.h"

#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "render/image_file.h"

namespace radiosity::render {

namespace {

// PFM's byte order is the header's sign, so a little-endian file reads the same on any host.
void putLittleEndian(float value, std::vector<unsigned char>& bytes) {
  uint32_t bits = std::bit_cast<uint32_t>(value);
  for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<unsigned char>(bits >> (8 * b)));
}

}  // namespace

void writePfmRgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  const size_t rowValues = static_cast<size_t>(width) * 3;
  if (width <= 0 || height <= 0 || rgb.size() != rowValues * static_cast<size_t>(height))
    throw Error(exit_code::kFailure, "cannot write '" + path + "': bad image size");
  writeImageFile(path, [&](std::FILE* file) {
    bool ok = std::fprintf(file, "PF\n%d %d\n-1.0\n", width, height) > 0;
    std::vector<unsigned char> row;
    row.reserve(rowValues * 4);
    for (int y = height - 1; y >= 0 && ok; --y) {
      row.clear();
      for (size_t i = 0; i < rowValues; ++i) putLittleEndian(rgb[y * rowValues + i], row);
      ok = std::fwrite(row.data(), 1, row.size(), file) == row.size();
    }
    return ok ? std::string() : std::string(std::strerror(errno));
  });
}

}  // namespace radiosity::render
