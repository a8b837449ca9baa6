#include "io/store/hdf5_util.h"

#include <utility>

namespace radiosity::h5 {

namespace {

using Closer = herr_t (*)(hid_t);

/// The call that closes an identifier of `type`; H5Idec_ref for any other kind.
Closer closerOf(H5I_type_t type) {
  static constexpr std::pair<H5I_type_t, Closer> kClosers[] = {
      {H5I_FILE, H5Fclose},       {H5I_GROUP, H5Gclose},     {H5I_DATASET, H5Dclose},
      {H5I_ATTR, H5Aclose},       {H5I_DATASPACE, H5Sclose}, {H5I_DATATYPE, H5Tclose},
      {H5I_GENPROP_LST, H5Pclose}};
  for (const auto& [kind, closer] : kClosers)
    if (kind == type) return closer;
  return H5Idec_ref;
}

}  // namespace

void Handle::close(const std::string& what) {
  if (!valid()) return;
  const herr_t status = closerOf(H5Iget_type(id_))(id_);
  // Whatever happened, the identifier is not ours any more: closing twice would hit another one.
  id_ = H5I_INVALID_HID;
  check(status, what);
}

void Handle::reset() noexcept {
  try {
    close("close");
  } catch (const Failure&) {
    // Cleanup after an earlier error, which is the one worth reporting.
  }
}

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

namespace {

// Walking upward visits the innermost call first: keep the first description that says something.
herr_t keepInnermost(unsigned, const H5E_error2_t* error, void* data) {
  auto& text = *static_cast<std::string*>(data);
  if (text.empty() && error->desc != nullptr && error->desc[0] != '\0') {
    text = error->desc;
    if (error->func_name != nullptr) text += " (in " + std::string(error->func_name) + ")";
  }
  return 0;
}

}  // namespace

std::string takeErrorText() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keepInnermost, &text);
  H5Eclear2(H5E_DEFAULT);
  return text.empty() ? "unknown HDF5 error" : text;
}

}  // namespace radiosity::h5
