// Private to io/: what the readers of HDF5 files (result and checkpoint) share. Serial HDF5 on
// the calling process; every problem with a file is an InputError naming the file and, where
// there is one, the dataset or attribute.
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "io/store/hdf5_util.h"
#include "io/store/result.h"

namespace radiosity::h5 {

/// Throws InputError("path: problem").
[[noreturn]] void fail(const std::string& path, const std::string& problem);

/// InputError unless `path` is an HDF5 file: missing, a directory or not HDF5. `kind` ("result
/// file") is what the caller expected to find.
void checkHdf5File(const std::string& path, const std::string& kind);

/// InputError naming the file and the object unless every dataset of the open `file` keeps its
/// data in the file itself: an external link, a dataset stored in external raw files
/// (H5Pset_external) or a virtual dataset reads other files, which may be FIFOs (a read that
/// blocks for ever) or outputs of this run. None of this program's files holds one.
void requireSelfContained(hid_t file, const std::string& path);

/// Opens an existing HDF5 file read-only with the default (serial) driver. A missing file, a
/// directory or a file that is not HDF5 throws InputError; `kind` ("result file") is what the
/// caller expected to find.
Handle openFile(const std::string& path, const std::string& kind);

/// Whether the object `name` ("/a/b") exists. H5Lexists fails rather than saying no when a group
/// on the way is missing, hence the walk; any other failure (damaged metadata) throws Failure.
bool exists(hid_t file, const std::string& name);

/// "float64", "int32", "uint64", "string"...: the names docs/result-format.md uses.
std::string typeName(hid_t type);
std::vector<hsize_t> shapeOf(hid_t space);
std::string shapeText(const std::vector<hsize_t>& dims);
/// The shortest text that reads back as the same double.
std::string exact(double value);

/// The names of the attributes of `object`, in name order.
std::vector<std::string> attributeNames(hid_t object);
/// A string attribute, fixed or variable length, without its padding.
std::string readString(hid_t attribute, hid_t type, const std::string& what);

/// The root's `kind` attribute of an open file, "" if there is none or it is not text. Throws
/// Failure.
std::string kindAttribute(hid_t file);
/// The `kind` of the HDF5 file at `path` ("radiosity checkpoint", …), "" when `path` is not a
/// regular HDF5 file that opens or has no text `kind`. Never throws: for isCheckpoint and kin.
std::string fileKind(const std::string& path);

/// "root attribute NAME" or "attribute NAME of /group", for messages.
std::string attributeLabel(hid_t object, const std::string& name);

/// An attribute of `object`, open, with its type and dataspace; InputError if it is missing.
struct OpenAttribute {
  std::string what;  ///< attributeLabel()
  Handle attribute, type, space;
};
OpenAttribute openAttribute(hid_t object, const std::string& path, const std::string& name);

/// A 1-D attribute of fixed-length strings (as h5::writeStringArrayAttribute writes them).
/// InputError if missing or not fixed-length text.
std::vector<std::string> readStringArrayAttribute(hid_t object, const std::string& path,
                                                  const std::string& name);

/// An attribute of `object` holding `count` numbers (a scalar or a 1-D array), converted to
/// int64, uint64 or double; InputError if missing, not numbers of that class or not `count`.
template <class T>
std::vector<T> readNumbers(hid_t object, const std::string& path, const std::string& name,
                           hssize_t count) {
  static_assert(std::is_arithmetic_v<T>);
  const OpenAttribute a = openAttribute(object, path, name);
  const std::string& what = a.what;
  const Handle &attribute = a.attribute, &type = a.type;
  const hssize_t found = H5Sget_simple_extent_npoints(a.space.get());
  if (found != count)
    fail(path, what + " holds " + std::to_string(found) + " values, expected " +
                   (count == 1 ? std::string("one") : std::to_string(count)));
  const bool wantFloat = std::is_floating_point_v<T>;
  if (H5Tget_class(type.get()) != (wantFloat ? H5T_FLOAT : H5T_INTEGER))
    fail(path, what + " is " + typeName(type.get()) + ", expected " +
                   (wantFloat ? "a floating-point number" : "an integer"));
  const hid_t memory = wantFloat             ? H5T_NATIVE_DOUBLE
                       : std::is_signed_v<T> ? H5T_NATIVE_INT64
                                             : H5T_NATIVE_UINT64;
  std::vector<T> values(count);
  if (H5Aread(attribute.get(), memory, values.data()) < 0)
    fail(path, "cannot read " + what + " as " + (wantFloat ? "float64" : typeName(memory)) + ": " +
                   takeErrorText());
  return values;
}

/// An attribute of `object` that holds one value, as int64, uint64, double or std::string.
template <class T>
T readAttribute(hid_t object, const std::string& path, const std::string& name) {
  if constexpr (std::is_same_v<T, std::string>) {
    const OpenAttribute a = openAttribute(object, path, name);
    const hssize_t found = H5Sget_simple_extent_npoints(a.space.get());
    if (found != 1)
      fail(path, a.what + " holds " + std::to_string(found) + " values, expected one");
    if (H5Tget_class(a.type.get()) != H5T_STRING)
      fail(path, a.what + " is " + typeName(a.type.get()) + ", not text");
    return readString(a.attribute.get(), a.type.get(), a.what);
  } else {
    return readNumbers<T>(object, path, name, 1).front();
  }
}

/// `value` as a narrower integer type; InputError naming attribute `name` if out of its range.
template <class Narrow>
Narrow narrowed(int64_t value, const std::string& path, const std::string& name) {
  if (value < std::numeric_limits<Narrow>::min() || value > std::numeric_limits<Narrow>::max())
    fail(path, "attribute " + name + " = " + std::to_string(value) + " is out of range");
  return static_cast<Narrow>(value);
}

/// InputError unless the file stores enough of dataset `name` (open as `dataset`, of dataspace
/// `space`) for the size it claims: at least 1/kMostCompression of its bytes. A small file whose
/// shape claimed far more rows than it stores (a dataset never written: no storage) made the
/// readers allocate for the claim before refusing it, and bad_alloc beyond; no compression HDF5
/// reads (deflate: at most about 1:1030) packs more.
void checkStored(hid_t dataset, hid_t space, const std::string& path, const std::string& name);
inline constexpr double kMostCompression = 1100;

/// Dataset `name`, open and checked: of the class of `memoryType` (float or integer), `columns`
/// values a row (0: a 1-D dataset) and `rows` rows (found from the file if negative, and
/// returned), stored in the file for as many as it claims (checkStored). InputError if it is
/// missing or of another class or shape.
struct OpenDataset {
  Handle dataset, space;
  int columns = 0;
  int64_t rows = 0;
};
OpenDataset openDataset(hid_t file, const std::string& path, const std::string& name,
                        hid_t memoryType, int columns, int64_t& rows);

/// InputError unless the rows `part` are in the open dataset `name`.
void checkRowRange(const OpenDataset& open, const std::string& path, const std::string& name,
                   Rows part);

/// The rows `part` of the open dataset `name` into `destination` (room for part.count ×
/// max(columns, 1) values of `memoryType`). InputError if the rows are not in it; a failing read
/// throws Failure. `transfer` H5P_DEFAULT reads on this process alone; a collective transfer list
/// (H5FD_MPIO_COLLECTIVE, on a file opened with the MPI-IO driver) makes the read collective:
/// every rank calls it, those with count 0 too.
void readRows(const OpenDataset& open, const std::string& path, const std::string& name,
              hid_t memoryType, Rows part, void* destination, hid_t transfer = H5P_DEFAULT);

/// The rows `part` of dataset `name` (all of them if none is given), converted to `memoryType`.
/// The dataset must have `rows` rows (found from the file if negative, and returned) of
/// `columns` values each (0: a 1-D dataset), of the class of `memoryType` (float or integer).
/// InputError if it is missing, of another class or shape, or the rows are not in it; a failing
/// read throws Failure (the caller knows what the file is meant to be).
template <class T>
std::vector<T> readDataset(hid_t file, const std::string& path, const std::string& name,
                           hid_t memoryType, int columns, int64_t& rows,
                           std::optional<Rows> part = std::nullopt) {
  const OpenDataset open = openDataset(file, path, name, memoryType, columns, rows);
  const Rows read = part.value_or(Rows{0, rows});
  checkRowRange(open, path, name, read);  // before allocating
  std::vector<T> values(static_cast<size_t>(read.count) *
                        static_cast<size_t>(std::max(columns, 1)));
  readRows(open, path, name, memoryType, read, values.data());
  return values;
}

/// The dataset `name` as a solve history (float64 [n, 4]: channel, iteration, residual,
/// seconds), checked: channels 0 to 2, iterations whole numbers from 0 to 2^53.
SolveHistory readSolveHistory(hid_t file, const std::string& path, const std::string& name);

}  // namespace radiosity::h5
