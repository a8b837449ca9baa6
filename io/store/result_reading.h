// Private to io/store: the result reader's work on a file already open, for `radiosity info`
// (result_info.cpp), which lists the file before it reads it.
#pragma once

#include <hdf5.h>

#include <string>

#include "io/store/result.h"

namespace radiosity {

/// Reads and checks the result file `file` (named `path` in messages). Throws InputError or
/// h5::Failure.
Result readOpenResult(hid_t file, const std::string& path);

}  // namespace radiosity
