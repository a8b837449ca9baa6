// STL, binary and ASCII, through OpenMesh after the strict walk of stl_structure.h; OpenMesh's
// reading is then checked against the walk, and the file's exact coordinates put in place.
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>

#include <cstdio>
#include <filesystem>
#include <istream>
#include <map>
#include <streambuf>
#include <string_view>

#include "core/error.h"
#include "io/scene/openmesh_mesh.h"
#include "io/scene/scene_internal.h"
#include "io/scene/stl_structure.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

/// A stream over text held elsewhere, without a copy (a binary STL may be a gigabyte).
class TextBuffer : public std::streambuf {
 public:
  explicit TextBuffer(std::string_view text) {
    char* begin = const_cast<char*>(text.data());  // only read: no put area is set
    setg(begin, begin, begin + text.size());
  }
};

/// OpenMesh reads the file's bytes (binary) or the walk's text of the facets (ASCII: one
/// keyword a line, which its line-based reader needs, with the file's own numbers), told which
/// explicitly rather than guessing. Returns its messages; InputError if it fails.
std::vector<std::string> readWithOpenMesh(PolyMesh& polyMesh, const std::string& path,
                                          const std::string& content, const StlFile& stl) {
  // Marks the vertices OpenMesh adds for a facet it cannot attach at a non-manifold edge.
  polyMesh.request_vertex_status();
  OpenMesh::IO::Options options;
  if (stl.binary) options += OpenMesh::IO::Options::Binary;
  options += OpenMesh::IO::Options::LSB;
  TextBuffer buffer(stl.binary ? std::string_view(content) : std::string_view(stl.openMeshText));
  std::istream in(&buffer);
  CaptureOpenMeshMessages capture;
  OpenMesh::IO::ImporterT<PolyMesh> importer(polyMesh);
  const bool ok = OpenMesh::IO::IOManager().read(in, ".stl", importer, options);
  std::vector<std::string> messages = capture.lines();
  if (!ok) {
    throw InputError(std::string(path)
                         .append(": not a readable STL file (OpenMesh's reader failed")
                         .append(joined(messages))
                         .append(")"));
  }
  return messages;
}

/// The facet (counting from 0) of each of OpenMesh's faces: its face k is the k-th facet the
/// walk did not drop. InputError if OpenMesh lost or added a facet.
std::vector<int64_t> facetOfFace(const StlFile& stl, size_t faces,
                                 const std::vector<std::string>& messages,
                                 const std::string& path) {
  const std::vector<uint64_t>& dropped = stl.facts.droppedFaces;
  if (faces + dropped.size() != stl.facts.faceCount) {
    throw InputError(std::string(path)
                         .append(": OpenMesh read ")
                         .append(std::to_string(faces))
                         .append(" of its ")
                         .append(std::to_string(stl.facts.faceCount - dropped.size()))
                         .append(" facets with three different corners")
                         .append(joined(messages)));
  }
  std::vector<int64_t> facet;
  facet.reserve(faces);
  size_t skipped = 0;
  for (uint64_t f = 0; f < stl.facts.faceCount; ++f) {
    if (skipped < dropped.size() && dropped[skipped] == f) {
      ++skipped;
      continue;
    }
    facet.push_back(static_cast<int64_t>(f));
  }
  return facet;
}

/// Whether OpenMesh's point is the walk's corner `value` (its points are the floats it read).
bool samePoint(const PolyMesh::Point& p, const std::array<float, 3>& value) {
  for (int k = 0; k < 3; ++k) {
    if (!sameStlCoordinate(static_cast<float>(p[k]), value[k])) return false;
  }
  return true;
}

std::string shown(const PolyMesh::Point& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
  return text;
}

/// How OpenMesh's mesh differs from the walk, "" if it does not: its vertices must be the
/// walk's distinct corners in order at their float values (after each, the copies it makes of
/// the corners of a facet it cannot attach at a non-manifold edge, marked so), and each face
/// the corners of its facet, in the file's order (up to where the loop starts).
std::string disagreement(const PolyMesh& polyMesh, const StlFile& stl,
                         const std::vector<int64_t>& facetOf) {
  const size_t fileVertices = stl.facts.vertices.size();
  std::vector<int64_t> walkVertex(polyMesh.n_vertices(), -1);  // -1: a copy
  size_t original = 0;
  for (const auto vh : polyMesh.vertices()) {
    if (polyMesh.status(vh).fixed_nonmanifold()) continue;
    if (original == fileVertices) break;
    if (!samePoint(polyMesh.point(vh), stl.floatVertices[original])) {
      return std::string("its vertex ")
          .append(std::to_string(original))
          .append(" (counting from 0) is at ")
          .append(shown(polyMesh.point(vh)))
          .append(", the file's corner at ")
          .append(
              shown(PolyMesh::Point(stl.floatVertices[original][0], stl.floatVertices[original][1],
                                    stl.floatVertices[original][2])));
    }
    walkVertex[vh.idx()] = static_cast<int64_t>(original++);
  }
  size_t originals = 0;
  for (const auto vh : polyMesh.vertices()) originals += !polyMesh.status(vh).fixed_nonmanifold();
  if (originals != fileVertices) {
    return std::string("it has ")
        .append(std::to_string(originals))
        .append(" distinct corners, the file ")
        .append(std::to_string(fileVertices));
  }
  for (const auto fh : polyMesh.faces()) {
    const std::array<int64_t, 3>& corners = stl.facets[facetOf[fh.idx()]];
    std::vector<OpenMesh::VertexHandle> read;
    for (const auto vh : polyMesh.fv_range(fh)) read.push_back(vh);
    bool same = false;
    for (size_t start = 0; read.size() == 3 && start < 3 && !same; ++start) {
      same = true;
      for (size_t i = 0; i < 3 && same; ++i) {
        const int64_t want = corners[(start + i) % 3];
        const int64_t got = walkVertex[read[i].idx()];
        same =
            (got == want || got < 0) && samePoint(polyMesh.point(read[i]), stl.floatVertices[want]);
      }
    }
    if (!same) {
      return std::string("its face of facet ")
          .append(std::to_string(facetOf[fh.idx()]))
          .append(" (counting from 0) has other corners");
    }
  }
  return {};
}

/// The label of each solid that has facets: one per name (the file's name for a solid without
/// one, and for a binary file), solids of the same name sharing it, in order of first use.
class SolidLabels {
 public:
  SolidLabels(const StlFile& stl, const std::string& path, Mesh& mesh)
      : stl_(stl), fileName_(std::filesystem::path(path).filename().string()), mesh_(mesh) {}
  int32_t of(int64_t facet) {
    const std::string& name = stl_.solidNames[stl_.facetSolid[facet]];
    const std::string& key = name.empty() ? fileName_ : name;
    const auto [it, added] =
        labelOf_.try_emplace(key, static_cast<int32_t>(mesh_.labelNames.size()));
    if (added) mesh_.labelNames.push_back(key);
    return it->second;
  }

 private:
  const StlFile& stl_;
  const std::string fileName_;
  Mesh& mesh_;
  std::map<std::string, int32_t> labelOf_;
};

void appendTriangle(const Triangle& t, int64_t facet, SolidLabels& labels, Mesh& mesh) {
  mesh.triangles.push_back(t);
  mesh.sourceFace.push_back(facet);
  mesh.reflectance.push_back(kDefaultReflectance);
  mesh.emission.push_back({0, 0, 0});
  mesh.label.push_back(labels.of(facet));
}

/// "PATH:LINE" for ASCII, "PATH" for binary.
std::string where(const std::string& path, long line) {
  return line > 0 ? std::string(path).append(":").append(std::to_string(line)) : path;
}

/// The warnings of what the walk forgave: facets with two equal corners, corners joined in
/// float precision.
void warnOfWalk(const StlFile& stl, const std::string& path, Mesh& mesh) {
  const std::vector<uint64_t>& dropped = stl.facts.droppedFaces;
  if (!dropped.empty()) {
    mesh.warnings.push_back(where(path, stl.facts.firstDroppedLine)
                                .append(": dropped ")
                                .append(std::to_string(dropped.size()))
                                .append(" facet(s) with two equal corners (no area), the first ")
                                .append("facet ")
                                .append(std::to_string(dropped[0]))
                                .append(" (counting from 0)"));
  }
  if (stl.joinedCorners > 0) {
    mesh.warnings.push_back(
        where(path, stl.firstJoinedLine)
            .append(": ")
            .append(std::to_string(stl.joinedCorners))
            .append(" corner(s) equal an earlier corner in float precision but not exactly ")
            .append("(OpenMesh joins corners by their float values): each is put at that ")
            .append("corner's position, the first in facet ")
            .append(std::to_string(stl.firstJoinedFacet))
            .append(" (counting from 0)"));
  }
}

/// OpenMesh's note that it could not attach a facet at a non-manifold edge or vertex (it then
/// attaches a copy of its corners; the mesh built here uses the file's corners instead).
bool isNonManifoldNote(const std::string& message) {
  return message.find("add_face: complex") != std::string::npos;
}

}  // namespace

Mesh readStl(const std::string& path) {
  std::string content;
  if (!readWholeFile(path, content)) throw InputError(path + ": cannot read file");
  const StlFile stl = checkStlFile(path, content);
  PolyMesh polyMesh;
  const std::vector<std::string> messages = readWithOpenMesh(polyMesh, path, content, stl);
  const std::vector<int64_t> facetOf = facetOfFace(stl, polyMesh.n_faces(), messages, path);
  const std::string differs = disagreement(polyMesh, stl, facetOf);

  Mesh mesh;
  for (const std::string& m : messages) {
    if (differs.empty() && isNonManifoldNote(m)) continue;
    mesh.warnings.push_back(std::string(path).append(": OpenMesh: ").append(m));
  }
  warnOfWalk(stl, path, mesh);
  mesh.warnings.push_back(path + ": no materials in STL; every facet gets ρ = 0.5, E = 0");
  SolidLabels labels(stl, path, mesh);
  if (differs.empty()) {
    // OpenMesh read what the walk did: the file's exact coordinates and corners.
    mesh.vertices = stl.facts.vertices;
    for (const auto fh : polyMesh.faces()) {
      const int64_t facet = facetOf[fh.idx()];
      const std::array<int64_t, 3>& c = stl.facets[facet];
      appendTriangle({c[0], c[1], c[2]}, facet, labels, mesh);
    }
    return mesh;
  }
  // Never put a vertex where OpenMesh did not: its floats, and the user told.
  mesh.warnings.push_back(std::string(path)
                              .append(": OpenMesh read the file otherwise than its strict walk (")
                              .append(differs)
                              .append("): its float coordinates are used, which may differ from ")
                              .append("the file's in the 8th digit"));
  mesh.vertices.reserve(polyMesh.n_vertices());
  for (const auto vh : polyMesh.vertices()) {
    const auto& p = polyMesh.point(vh);
    mesh.vertices.push_back({p[0], p[1], p[2]});
  }
  for (const auto fh : polyMesh.faces()) {
    std::vector<int64_t> corners;
    for (const auto vh : polyMesh.fv_range(fh)) corners.push_back(vh.idx());
    if (corners.size() != 3) {
      throw InputError(std::string(path)
                           .append(": OpenMesh read facet ")
                           .append(std::to_string(facetOf[fh.idx()]))
                           .append(" (counting from 0) with ")
                           .append(std::to_string(corners.size()))
                           .append(" corners"));
    }
    appendTriangle({corners[0], corners[1], corners[2]}, facetOf[fh.idx()], labels, mesh);
  }
  return mesh;
}

}  // namespace radiosity::detail
