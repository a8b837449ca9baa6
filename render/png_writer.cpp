#include "render/png_writer.h"


#include <fcntl.h>
#include <png.h>
#include <unistd.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "io/atomic_file.h"
#include "io/io.h"

namespace radiosity::render {

namespace {

struct PngFailure {
  std::jmp_buf jump;
  char message[256];
};

void onPngError(png_structp png, png_const_charp message) {
  auto* failure = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(failure->message, sizeof failure->message, "%s", message);
  std::longjmp(failure->jump, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

// libpng reports errors by longjmp, which must not cross C++ objects with destructors: this
// function holds only plain data. Returns false with failure.message set.
bool encode(std::FILE* file, int width, int height, const uint8_t* rgb, PngFailure& failure) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &failure, onPngError, onPngWarning);
  if (!png) {
    std::snprintf(failure.message, sizeof failure.message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(failure.jump)) {
    if (!info) std::snprintf(failure.message, sizeof failure.message, "out of memory");
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y)
    png_write_row(png, rgb + static_cast<size_t>(y) * static_cast<size_t>(width) * 3);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

// Opens a new file beside `path` with the usual permissions (0666 less the umask).
int createTemporary(const std::string& path, std::string& tempPath) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    tempPath = temporaryNameFor(path);
    int fd = open(tempPath.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  return -1;
}

}  // namespace

void writePngRgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 ||
      rgb.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 3)
    throw Error(exit_code::kFailure, "cannot write '" + path + "': bad image size");
  auto fail = [&](const std::string& why) {
    return Error(exit_code::kFailure, "cannot write the picture '" + path + "': " + why);
  };

  std::string tempPath;
  int fd = createTemporary(path, tempPath);
  if (fd < 0) throw fail(std::strerror(errno));
  std::FILE* file = fdopen(fd, "wb");
  if (!file) {
    int error = errno;
    close(fd);
    std::remove(tempPath.c_str());
    throw fail(std::strerror(error));
  }

  PngFailure failure{};
  std::string why;
  if (!encode(file, width, height, rgb.data(), failure)) why = failure.message;
  // A full disk may only show when the buffers are flushed, so every step is checked.
  auto check = [&](bool stepOk) {
    if (!stepOk && why.empty()) why = std::strerror(errno);
  };
  check(std::fflush(file) == 0);
  if (why.empty()) check(fsync(fileno(file)) == 0);
  check(std::fclose(file) == 0);
  if (why.empty()) check(std::rename(tempPath.c_str(), path.c_str()) == 0);
  if (!why.empty()) {
    std::remove(tempPath.c_str());
    throw fail(why);
  }
  removeStaleTemporaries(path);
}

}  // namespace radiosity::render
