#include "io/store/hdf5_util.h"

namespace radiosity::h5 {

void Handle::close(const std::string& what) {
  if (!valid()) return;
  herr_t status = -1;
  switch (H5Iget_type(id_)) {
    case H5I_FILE:
      status = H5Fclose(id_);
      break;
    case H5I_GROUP:
      status = H5Gclose(id_);
      break;
    case H5I_DATASET:
      status = H5Dclose(id_);
      break;
    case H5I_ATTR:
      status = H5Aclose(id_);
      break;
    case H5I_DATASPACE:
      status = H5Sclose(id_);
      break;
    case H5I_DATATYPE:
      status = H5Tclose(id_);
      break;
    case H5I_GENPROP_LST:
      status = H5Pclose(id_);
      break;
    default:
      status = H5Idec_ref(id_);
      break;
  }
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
