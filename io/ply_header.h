// Private to io/: what the OpenMesh PLY reader needs to be told about a PLY header. Our own scan,
// because OpenMesh 9 reports neither the custom face properties' types nor their order.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace radiosity::detail {

struct PlyProperty {
  std::string name;
  std::string type;  ///< the value type as written ("uchar", "float32", ...); entries of a list
  bool isList = false;
  size_t typeWord = 1;  ///< which word of the property line is `type`
  long line = 0;        ///< 1-based line in the file
};

struct PlyElement {
  std::string name;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool ascii = false;
  std::vector<PlyElement> elements;
  size_t headerEnd = 0;  ///< offset just after the "end_header" line

  const PlyProperty* faceProperty(const std::string& name) const;
};

/// Scans the header of the PLY file whose text (the whole file, or at least its header) is
/// `content`. Throws InputError naming `path` and the line if the header is malformed.
PlyHeader scanPlyHeader(const std::string& path, const std::string& content);

/// True for the 8-bit PLY types (char, uchar, int8, uint8).
bool isEightBitPlyType(const std::string& type);

/// The emission a PLY file gives in the face properties emit_red, emit_green, emit_blue.
struct PlyEmission {
  bool present = false;
  std::array<std::string, 3> names = {"emit_red", "emit_green", "emit_blue"};
  std::array<double, 3> scale = {1, 1, 1};  ///< 1/255 for 8-bit values, like colours
  /// An ASCII file with 8-bit custom properties: OpenMesh 9 must read a retyped copy.
  bool needsRetyping = false;
};

/// Reads the header of the PLY file `path` and checks its emit_* face properties: all three or
/// none, scalar, of type float, double or uchar. Throws InputError naming file and line.
PlyEmission findPlyEmission(const std::string& path);

/// OpenMesh 9's ASCII PLY reader reads an 8-bit custom property as a single character
/// (`stream >> unsigned char`), misreading the rest of the file. Returns the ASCII PLY `content`
/// with such properties of the vertex and face elements declared "int" instead (the same text
/// reads as the same number).
std::string retypeEightBitCustomProperties(const std::string& path, const std::string& content);

}  // namespace radiosity::detail
