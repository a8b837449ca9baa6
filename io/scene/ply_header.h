// Private to io/: what the OpenMesh PLY reader needs to be told about a PLY header. Our own scan,
// because OpenMesh 9 reports neither the custom face properties' types nor their order.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace radiosity::detail {

struct PlyProperty {
  std::string name;
  std::string type;  ///< the value type as written ("uchar", "float32", ...); entries of a list
  bool isList = false;
  std::string countType;  ///< a list's count type ("uchar", ...)
  size_t typeWord = 1;    ///< which word of the property line is `type`
  long line = 0;          ///< 1-based line in the file
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;  ///< how many the header declares
  long line = 0;       ///< 1-based line of the element line
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool ascii = false;
  bool bigEndian = false;  ///< binary_big_endian
  std::vector<PlyElement> elements;
  size_t headerEnd = 0;  ///< offset just after the "end_header" line
  long headerLines = 0;  ///< 1-based line of "end_header"

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

/// What the strict walk of a PLY or OFF body learnt that OpenMesh would lose or garble.
struct MeshBodyFacts {
  /// Every vertex's x, y, z exactly as the file writes them: OpenMesh 9 reads them through
  /// float, losing double precision.
  std::vector<Vec3> vertices;
  /// File indices (ascending) of the triangles that name a vertex twice: no area, dropped with a
  /// warning as in OBJ (OpenMesh refuses them; its face k is the k-th face not listed here).
  std::vector<uint64_t> droppedFaces;
  long firstDroppedLine = 0;  ///< text files: the line of the first dropped face; 0 if binary
  uint64_t faceCount = 0;     ///< faces in the file, dropped ones included
  /// Each face's colour as the file writes it, where it is of type float or double: OpenMesh
  /// passes it through a byte (0.5 became 0.498). Empty for byte colours or none.
  std::vector<Rgb> faceColours;
};

/// Walks the body of the PLY file `content` (header as scanned by scanPlyHeader) the way a strict
/// reader would, before OpenMesh (which trusts the file) reads it. ASCII: every element exactly
/// one non-blank line with exactly the values its properties need (a list: its count, then that
/// many entries), each a whole number of its type and within its range (finite for float and
/// double), nothing after the last element. Binary: the file exactly as long as the elements
/// need, float and double values finite. Both: a face's vertex_indices at least 3, each in
/// [0, vertex count), a face of more than 3 corners never naming one twice. Throws InputError
/// naming the file and the line (ASCII) or the element (binary).
MeshBodyFacts checkPlyBody(const std::string& path, const std::string& content,
                           const PlyHeader& header);

}  // namespace radiosity::detail
