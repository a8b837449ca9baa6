// The XDMF 3 sidecar of a result file (RESULT.xmf), so that ParaView opens a result with no extra
// step and shows the answer first: the display mesh (or, for a result without /display, the
// patches' mesh); as point data the tone-mapped luminance of the smooth radiosity first (what
// ParaView colours by; a thermal run's one-channel B instead), then the smooth radiosity; as cell
// data every /patches dataset; B's channels also apart ("radiosity_red"), names with the unit the
// file states ("area [mm^2]"), and the labels of /patches/group as field data ("group 3: left").
// All is read from the .h5 named by its file name alone, so that the pair can move together.
// (ParaView 5.11's XDMF 3 reader looks for it beside a sidecar opened by a bare file name, e.g.
// pvpython's OpenDataFile("r.xmf"), as "r.xmfr.h5" and aborts: no relative name avoids that;
// "./r.xmf" or an absolute path opens it.)
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
