// Private to io/: what the HDF5 result writer and reader share. Owning HDF5 identifiers, and
// turning HDF5's error stack into exception messages instead of letting it print to stderr.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace radiosity::h5 {

/// Rows [first, first + count) of a dataset: the part one rank writes, or a part read.
struct Rows {
  int64_t first = 0;
  int64_t count = 0;
};

/// An HDF5 call failed. The message names the call and HDF5's most specific description; the
/// writer and reader add the file name and turn it into the error type of core/error.h.
class Failure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Owns one HDF5 identifier (file, group, dataset, attribute, dataspace, datatype or property
/// list) and closes it with the matching H5?close. Never holds a predefined type such as
/// H5T_NATIVE_DOUBLE, which must not be closed.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

  /// Closes now and throws Failure if that fails: for a file, closing is when data are flushed.
  void close(const std::string& what);
  /// Closes now, ignoring failure (cleanup after another error).
  void reset() noexcept;

 private:
  hid_t id_ = H5I_INVALID_HID;
};

/// Stops HDF5 printing its error stack for the guard's lifetime; restores the previous handler.
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

/// The innermost (most specific) description on HDF5's error stack, which is then cleared.
std::string takeErrorText();

/// Throws Failure("call: <HDF5 description>") if `result` is negative, the HDF5 failure value of
/// hid_t, herr_t and htri_t alike. Returns `result`.
template <class T>
T check(T result, const std::string& call) {
  if (result < 0) throw Failure(call + ": " + takeErrorText());
  return result;
}

/// check() for a call returning a new identifier, which the returned Handle then owns.
inline Handle own(hid_t id, const std::string& call) { return Handle(check(id, call)); }

}  // namespace radiosity::h5
