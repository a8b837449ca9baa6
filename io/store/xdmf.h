// The XDMF 3 sidecar of a result file (RESULT.xmf), so that ParaView and VisIt open a result
// with no extra step: the display mesh (or, for a result without /display, the patches' mesh),
// every /patches dataset as cell data and the smooth radiosity as point data, all read from the
// .h5 named by its file name alone, so that the pair can move together.
#pragma once

#include <string>

namespace radiosity {

/// RESULT.xmf for RESULT.h5 (the extension replaced).
std::string xdmfPathFor(const std::string& resultPath);

/// What the sidecar shows.
struct XdmfSidecar {
  std::string text;
  bool smooth = false;  ///< the file has /display: point data; otherwise cell data only
};

/// The sidecar of the result file at `resultFile` (read serially for the shapes and types of its
/// datasets; it may still be under a temporary name), naming it as `reference`. Throws
/// InputError if it is not a result file.
XdmfSidecar xdmfFor(const std::string& resultFile, const std::string& reference);

}  // namespace radiosity
