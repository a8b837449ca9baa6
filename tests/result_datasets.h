// A dataset of a result file read whole, for the tests of what a result holds (serial HDF5).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "io/store/hdf5_read.h"

namespace radiosity::testing {

/// Dataset `name` of [n, `columns`] (0: [n]) of `file`, doubles or int64.
template <class T>
std::vector<T> readAll(const std::filesystem::path& file, const std::string& name,
                       int columns = 3) {
  h5::Handle handle = h5::openFile(file.string(), "result file");
  int64_t rows = -1;
  const hid_t type = std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64;
  return h5::readDataset<T>(handle.get(), file.string(), name, type, columns, rows);
}

}  // namespace radiosity::testing
