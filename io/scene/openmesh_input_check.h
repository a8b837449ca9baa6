// Private to io/scene/: the strict walk of PLY and OFF files before OpenMesh, which trusts what
// a file says (a PLY header without end_header, or with a bad count, makes it loop forever; a
// huge element, face or list count makes it reserve or loop without bound).
#pragma once

#include <string>

#include "io/scene/ply_header.h"

namespace radiosity::detail {

/// Walks the structure of the PLY file `content` (magic, format, header keywords and types,
/// counts backed by the file's size). Throws InputError naming `path`.
void checkPlyStructure(const std::string& path, const std::string& content);

/// A text or binary OFF file walked strictly: counts, one vertex a line with exactly the values
/// its header needs, faces of at least 3 corners with indices in range, nothing after the last
/// face. Throws InputError naming `path` and the line.
struct OffFile {
  MeshBodyFacts facts;
  /// A text file with '#' comments: its text with them blanked out (same lines, same layout),
  /// for OpenMesh, which does not know comments; otherwise empty.
  std::string withoutComments;
};
OffFile checkOffFile(const std::string& path, const std::string& content);

}  // namespace radiosity::detail
