// The checks of an HDF5 scene file's rows (scene_file_checks.h), in the words of the format
// (io/store/scene_file_format.h).
#include "io/store/scene_file_checks.h"

#include <cmath>

#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/scene_file_format.h"

namespace radiosity::scene_file_checks {
namespace {

namespace format = scene_format;
using h5::fail;

std::string number(double x) { return h5::exact(x); }

}  // namespace

std::string rowOf(const char* name, int64_t row) {
  return std::string("dataset ") + name + ": row " + std::to_string(row);
}

void checkVertices(const std::string& path, int64_t first, int64_t count, const Vec3* v) {
  for (int64_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) {
      const double x = v[i][k];
      if (!std::isfinite(x) || std::abs(x) > kMaxCoordinate)
        fail(path, rowOf(format::kVertices, first + i) + " has coordinate " + number(x) +
                       " (must be finite, |x| <= 1e30)");
    }
}

void checkTriangles(const std::string& path, int64_t first, int64_t count, const Triangle* t,
                    int64_t nv) {
  for (int64_t i = 0; i < count; ++i)
    for (int64_t v : t[i])
      if (v < 0 || v >= nv)
        fail(path, rowOf(format::kTriangles, first + i) + " refers to vertex " + std::to_string(v) +
                       " (" + std::to_string(nv) + " vertices, counted from 0)");
}

void checkIndices(const std::string& path, const char* name, int64_t first, int64_t count,
                  const int32_t* values, int64_t end, const char* of) {
  for (int64_t i = 0; i < count; ++i)
    if (values[i] < 0 || values[i] >= end)
      fail(path, rowOf(name, first + i) + " holds " + std::to_string(values[i]) +
                     ", not a row of " + of + " (" + std::to_string(end) + " rows)");
}

void checkMaterials(const std::string& path, const std::vector<Rgb>& reflectance,
                    const std::vector<Rgb>& emission) {
  for (size_t m = 0; m < reflectance.size(); ++m)
    for (int c = 0; c < 3; ++c) {
      const double rho = reflectance[m][c], e = emission[m][c];
      if (!(rho >= 0 && rho <= 1))  // also refuses NaN
        fail(path, rowOf(format::kReflectance, static_cast<int64_t>(m)) + " channel " +
                       std::to_string(c) + " holds " + number(rho) + " (must be within [0, 1])");
      if (!(e >= 0) || !(e <= kMaxEmission))
        fail(path, rowOf(format::kEmission, static_cast<int64_t>(m)) + " channel " +
                       std::to_string(c) + " holds " + number(e) +
                       " (must be finite, >= 0 and <= 1e100)");
    }
}

}  // namespace radiosity::scene_file_checks
