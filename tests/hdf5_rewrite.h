// Damaging a checkpoint on purpose, as the refusal tests need: one dataset's values changed in
// place through serial HDF5, so that its Fletcher32 checksum is right and only the reader's own
// checks can find the damage.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <vector>

namespace radiosity::testing {

/// Rewrites dataset `name` of the open HDF5 file `file` whole, with `change` applied to its
/// values (read as T through `memoryType`).
template <class T, class Change>
void rewriteDataset(hid_t file, const char* name, hid_t memoryType, Change change) {
  const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
  ASSERT_GE(dataset, 0) << name;
  const hid_t space = H5Dget_space(dataset);
  std::vector<T> values(H5Sget_simple_extent_npoints(space));
  H5Sclose(space);
  ASSERT_GE(H5Dread(dataset, memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  change(values);
  ASSERT_GE(H5Dwrite(dataset, memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(dataset);
}

/// The same on the file at `path` (serial HDF5, so a checkpoint's checksum stays right).
template <class T, class Change>
void rewrite(const std::filesystem::path& path, const char* name, hid_t memoryType, Change change) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  rewriteDataset<T>(file, name, memoryType, change);
  H5Fclose(file);
}

}  // namespace radiosity::testing
