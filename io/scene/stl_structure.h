// Private to io/scene/: the strict walk of an STL file before OpenMesh reads it. OpenMesh's STL
// reader trusts the file and reports nothing: its ASCII reader goes by lines, looks only for
// "facet normal" and "outer" anywhere in a line and takes the next three lines as vertices
// whatever they say (in a solid named "outer wall" the first facet is lost; "1e5x" reads as
// 1e5, "nan" or a missing value as 0 or the previous corner's value, and a facet so collapsed
// is skipped); a binary file cut short is taken for ASCII and read as no facets. It joins
// corners by their float values.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/scene/ply_header.h"

namespace radiosity::detail {

/// What the walk of an STL file found.
struct StlFile {
  bool binary = false;
  /// vertices: the distinct corners in order of first appearance, as OpenMesh numbers them (it
  /// joins corners whose float values are equal), each with the file's exact value (ASCII: the
  /// double the text writes; binary: the float widened). faceCount: the facets. droppedFaces:
  /// the facets two of whose corners are the same vertex (OpenMesh skips them silently);
  /// firstDroppedLine: the ASCII line of the first.
  MeshBodyFacts facts;
  /// The float value of each of facts.vertices, as OpenMesh reads it (ASCII: the file's text
  /// read as a float, not the double rounded again).
  std::vector<std::array<float, 3>> floatVertices;
  /// Each facet's corners, as indices into facts.vertices, in the file's order.
  std::vector<std::array<int64_t, 3>> facets;
  /// ASCII: the solid (index into solidNames) each facet is in; binary: all 0.
  std::vector<int32_t> facetSolid;
  /// ASCII: each `solid` block's name as written (trimmed; "" for none); binary: one "".
  std::vector<std::string> solidNames;
  /// Corners whose exact value differs from that of the earlier corner they share a float value
  /// with (so they are that vertex, at its position), and where the first is: its line (ASCII)
  /// or 0, and its facet (counting from 0).
  uint64_t joinedCorners = 0;
  long firstJoinedLine = 0;
  uint64_t firstJoinedFacet = 0;
  /// ASCII: the facets again, one keyword a line as OpenMesh's reader needs them, each vertex
  /// with the file's own number text (for OpenMesh to parse), the names left out. Binary: empty
  /// (OpenMesh reads the file's bytes).
  std::string openMeshText;
};

/// Whether the float coordinates `a` and `b` are the same for joining corners: equal, or both
/// of magnitude below FLT_MIN (+0 and -0, subnormals). OpenMesh joins values at most FLT_MIN
/// apart, which only values that small (up to about 2e-38) can be; where it joins otherwise than
/// this, the reader's check of OpenMesh's vertices against the walk's finds it.
bool sameStlCoordinate(float a, float b);

/// Walks the STL file `content` strictly. Binary iff its size is 84 + 50 × the facet count at
/// byte 80 (as OpenMesh decides); else ASCII, beginning with `solid`. ASCII: one or more
/// `solid [name]` … `endsolid [name]` blocks of `facet normal nx ny nz` / `outer loop` /
/// `vertex x y z` × 3 / `endloop` / `endfacet` (keywords in any case, any whitespace), numbers
/// whole, coordinates finite and within ±1e30, nothing but whitespace after the last
/// `endsolid`. Binary: coordinates finite and within ±1e30 (normals are not looked at). At
/// least one facet. Throws InputError naming `path` and the line (ASCII) or facet (binary).
StlFile checkStlFile(const std::string& path, const std::string& content);

}  // namespace radiosity::detail
