// PLY and OFF through OpenMesh. Its types stay in io/scene/ (openmesh_mesh.h).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/error.h"
#include "io/scene/openmesh_input_check.h"
#include "io/scene/openmesh_mesh.h"
#include "io/scene/ply_header.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

/// OpenMesh 9.0's PLY and OFF readers set the colour (and other attributes) of a face even when
/// add_face() refused it (an invalid handle, -1): a write before the start of the colour array.
/// This importer drops those writes; the refused face itself is reported through omerr. And
/// they read coordinates through float: given the file's own values (`exact`, from the strict
/// walk of the body; may be empty), it puts those in place instead.
class GuardedImporter : public OpenMesh::IO::ImporterT<PolyMesh> {
 public:
  GuardedImporter(PolyMesh& mesh, const std::vector<Vec3>& exact)
      : ImporterT(mesh), mesh_(mesh), exact_(exact) {}
  using ImporterT::set_color;
  using ImporterT::set_point;
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    return exactly(ImporterT::add_vertex(p));
  }
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    return exactly(ImporterT::add_vertex(p));
  }
  void set_point(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& p) override {
    ImporterT::set_point(v, p);
    exactly(v);
  }
  using ImporterT::set_normal;
  using ImporterT::set_status;
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec3uc& c) override { ifValid(f, c); }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec4uc& c) override { ifValid(f, c); }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec3f& c) override { ifValid(f, c); }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec4f& c) override { ifValid(f, c); }
  void set_normal(OpenMesh::FaceHandle f, const OpenMesh::Vec3f& n) override {
    if (f.is_valid()) ImporterT::set_normal(f, n);
  }
  void set_normal(OpenMesh::FaceHandle f, const OpenMesh::Vec3d& n) override {
    if (f.is_valid()) ImporterT::set_normal(f, n);
  }
  void set_status(OpenMesh::FaceHandle f, const OpenMesh::Attributes::StatusInfo& s) override {
    if (f.is_valid()) ImporterT::set_status(f, s);
  }
  void set_face_texindex(OpenMesh::FaceHandle f, int id) override {
    if (f.is_valid()) ImporterT::set_face_texindex(f, id);
  }

 private:
  template <class C>
  void ifValid(OpenMesh::FaceHandle f, const C& c) {
    if (f.is_valid()) ImporterT::set_color(f, c);
  }
  /// Vertex k of the file gets exact_[k]; vertices OpenMesh adds to split a non-manifold face
  /// copy their original's point, exact already.
  OpenMesh::VertexHandle exactly(OpenMesh::VertexHandle v) {
    if (v.is_valid() && static_cast<size_t>(v.idx()) < exact_.size()) {
      const Vec3& e = exact_[v.idx()];
      mesh_.set_point(v, OpenMesh::Vec3d(e.x, e.y, e.z));
    }
    return v;
  }

  PolyMesh& mesh_;
  const std::vector<Vec3>& exact_;
};

/// OpenMesh::IO::read_mesh() with the GuardedImporter.
bool readMeshGuarded(PolyMesh& mesh, const std::string& path, const std::vector<Vec3>& exact,
                     OpenMesh::IO::Options& options) {
  mesh.clear();
  GuardedImporter importer(mesh, exact);
  return OpenMesh::IO::IOManager().read(path, importer, options);
}
bool readMeshGuarded(PolyMesh& mesh, std::istream& in, const std::string& extension,
                     const std::vector<Vec3>& exact, OpenMesh::IO::Options& options) {
  mesh.clear();
  GuardedImporter importer(mesh, exact);
  return OpenMesh::IO::IOManager().read(in, extension, importer, options);
}

/// Reads `path` with OpenMesh; a PLY file with emit_* face properties with its custom properties
/// (OpenMesh names them as in the file), through a retyped copy where OpenMesh needs one.
/// `plyText`: the PLY file's content as OpenMesh must read it, if not the file (may be empty).
bool readWithOpenMesh(PolyMesh& polyMesh, const std::string& path, const PlyEmission& emission,
                      const std::string& plyText, const std::vector<Vec3>& exact,
                      OpenMesh::IO::Options& options) {
  if (emission.present) options += OpenMesh::IO::Options::Custom;
  if (!emission.needsRetyping && plyText.empty())
    return readMeshGuarded(polyMesh, path, exact, options);
  std::string content = plyText;
  if (content.empty() && !readWholeFile(path, content))
    throw InputError(path + ": cannot read file");
  if (emission.needsRetyping) content = retypeEightBitCustomProperties(path, content);
  std::istringstream in(content, std::ios::binary);
  return readMeshGuarded(polyMesh, in, ".ply", exact, options);
}

/// OpenMesh knows no obj_info header lines (it warns of each of their words as an unsupported
/// keyword): `content` with them made comments of the same length; false if it has none.
bool commentObjInfo(std::string& content) {
  const size_t headerEnd = content.find("end_header");
  bool changed = false;
  for (size_t at = content.find("obj_info"); at < headerEnd;
       at = content.find("obj_info", at + 8)) {
    if (at > 0 && content[at - 1] != '\n' && content[at - 1] != '\r') continue;
    content.replace(at, 8, "comment ");
    changed = true;
  }
  return changed;
}

/// Reads the text OFF file `path` from `text` (its content with the comments blanked out).
/// IOManager's stream read would not look at the header line (COFF, ...), so the OFF reader is
/// asked to look at the file's own first line (the same as the text's) before reading the text.
bool readOffText(PolyMesh& mesh, const std::string& path, const std::string& text,
                 const std::vector<Vec3>& exact, OpenMesh::IO::Options& options) {
  OpenMesh::IO::_OFFReader_& reader = OpenMesh::IO::OFFReader();
  if (!reader.can_u_read(path)) return false;
  mesh.clear();
  GuardedImporter importer(mesh, exact);
  std::istringstream in(text, std::ios::binary);
  importer.prepare();
  const bool ok = reader.read(in, importer, options);
  importer.finish();
  return ok;
}

/// The values of the face property `name` that OpenMesh created from the file, whatever its
/// type, times `scale`; empty if OpenMesh did not create it.
template <class T>
bool copyFaceProperty(const PolyMesh& mesh, const std::string& name, double scale,
                      std::vector<double>& out) {
  OpenMesh::FPropHandleT<T> handle;
  if (!mesh.get_property_handle(handle, name)) return false;
  for (const auto fh : mesh.faces())
    out.push_back(scale * static_cast<double>(mesh.property(handle, fh)));
  return true;
}
std::vector<double> faceValues(const PolyMesh& mesh, const std::string& name, double scale) {
  std::vector<double> out;
  copyFaceProperty<float>(mesh, name, scale, out) ||
      copyFaceProperty<double>(mesh, name, scale, out) ||
      copyFaceProperty<unsigned char>(mesh, name, scale, out) ||
      copyFaceProperty<int>(mesh, name, scale, out);
  return out;
}

/// The file's extension in lower case (".ply", ".off").
std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

/// What the strict checks before OpenMesh found: the body's facts (the exact coordinates, the
/// faces to drop) and, where OpenMesh must read another text than the file's, that text.
struct CheckedInput {
  MeshBodyFacts facts;
  std::string offText;
  std::string plyText;  ///< a PLY file with obj_info lines: its text with them as comments
};

CheckedInput checkInput(const std::string& path, const std::string& extension) {
  CheckedInput input;
  std::string content;
  if (!readWholeFile(path, content)) throw InputError(path + ": cannot read file");
  if (extension == ".ply") {
    checkPlyStructure(path, content);
    input.facts = checkPlyBody(path, content, scanPlyHeader(path, content));
    if (commentObjInfo(content)) input.plyText = std::move(content);
  }
  if (extension == ".off") {
    OffFile off = checkOffFile(path, content);
    input.facts = std::move(off.facts);
    input.offText = std::move(off.withoutComments);
  }
  return input;
}

/// Reads the file into `polyMesh` with OpenMesh, its messages captured and returned. InputError
/// if OpenMesh fails.
std::vector<std::string> readPolyMesh(PolyMesh& polyMesh, const std::string& path,
                                      const PlyEmission& emission, const CheckedInput& input,
                                      OpenMesh::IO::Options& options) {
  CaptureOpenMeshMessages capture;
  const bool ok =
      input.offText.empty()
          ? readWithOpenMesh(polyMesh, path, emission, input.plyText, input.facts.vertices, options)
          : readOffText(polyMesh, path, input.offText, input.facts.vertices, options);
  std::vector<std::string> messages = capture.lines();
  if (!ok)
    throw InputError(path + ": not a readable mesh file (OpenMesh reader failed" +
                     joined(messages) + ")");
  return messages;
}

/// OpenMesh's messages as warnings, but for a face it skipped (bad input for us: InputError)
/// and its refusal of the faces the checks dropped (warned of once, by fileFaces).
void takeMessages(const std::vector<std::string>& messages, const MeshBodyFacts& facts,
                  const std::string& path, Mesh& mesh) {
  for (const auto& m : messages) {
    // OpenMesh skips faces with bad indices instead of failing; for us that is bad input.
    if (m.find("invalid vertex index") != std::string::npos) {
      throw InputError(path + ": face refers to a vertex that does not exist (" + m + ")" +
                       (path.ends_with(".off") || path.ends_with(".OFF")
                            ? "; note: face colours in OFF need a COFF header"
                            : ""));
    }
    // Its refusal of the triangles that name a vertex twice, which are reported below.
    if (!facts.droppedFaces.empty() && m.find("invalid faces") != std::string::npos) continue;
    if (!facts.droppedFaces.empty() && m.find("equal vertices") != std::string::npos) continue;
    mesh.warnings.push_back(path + ": OpenMesh: " + m);
  }
}

/// The file's face of each of OpenMesh's faces (its k-th face is the file's k-th face not
/// dropped), with a warning for the dropped ones. InputError if OpenMesh lost a face.
std::vector<int64_t> fileFaces(const MeshBodyFacts& facts, size_t readFaces,
                               const std::vector<std::string>& messages, const std::string& path,
                               Mesh& mesh) {
  if (readFaces + facts.droppedFaces.size() != facts.faceCount)
    throw InputError(path + ": OpenMesh read " + std::to_string(readFaces) + " of its " +
                     std::to_string(facts.faceCount) + " faces" + joined(messages));
  std::vector<int64_t> fileFace;
  fileFace.reserve(readFaces);
  for (int64_t face = 0, skipped = 0; fileFace.size() < readFaces; ++face) {
    if (skipped < static_cast<int64_t>(facts.droppedFaces.size()) &&
        facts.droppedFaces[skipped] == static_cast<uint64_t>(face)) {
      ++skipped;
      continue;
    }
    fileFace.push_back(face);
  }
  if (!facts.droppedFaces.empty()) {
    const std::string where =
        facts.firstDroppedLine > 0 ? path + ":" + std::to_string(facts.firstDroppedLine) : path;
    mesh.warnings.push_back(where + ": dropped " + std::to_string(facts.droppedFaces.size()) +
                            " face(s) that name a vertex twice (no area), the first face " +
                            std::to_string(facts.droppedFaces[0]) + " (counting from 0)");
  }
  return fileFace;
}

/// The emission of every face, per channel, from a PLY file's emit_* properties (empty without
/// them). InputError if OpenMesh did not read one.
std::array<std::vector<double>, 3> emittedPerFace(const PolyMesh& polyMesh,
                                                  const PlyEmission& emission,
                                                  const std::string& path) {
  std::array<std::vector<double>, 3> emitted;
  if (!emission.present) return emitted;
  for (int c = 0; c < 3; ++c) {
    emitted[c] = faceValues(polyMesh, emission.names[c], emission.scale[c]);
    if (emitted[c].size() != polyMesh.n_faces()) {
      throw InputError(path + ": OpenMesh did not read the face property '" + emission.names[c] +
                       "' (it must come after vertex_indices)");
    }
  }
  return emitted;
}

/// What each of OpenMesh's faces brings besides its corners: its face in the file, its colour
/// (ρ) if the file has colours (`exactColours`, per file face, as the file writes them where
/// they are floats; else OpenMesh's), and E per channel if the file gives it.
struct FaceValues {
  const std::vector<int64_t>& fileFace;
  bool hasColour = false;
  const std::vector<Rgb>& exactColours;
  bool withEmission = false;
  const std::array<std::vector<double>, 3>& emitted;
};

/// Appends OpenMesh's faces to `mesh` as triangles, each with its file face, ρ (the face colour,
/// if the file has colours) and E. InputError for a face whose outline crosses itself.
void appendFaces(const PolyMesh& polyMesh, const FaceValues& values, const std::string& path,
                 Mesh& mesh) {
  const std::vector<int64_t>& fileFace = values.fileFace;
  const bool hasColour = values.hasColour, withEmission = values.withEmission;
  const std::vector<Rgb>& exactColours = values.exactColours;
  const std::array<std::vector<double>, 3>& emitted = values.emitted;
  AddedVertices added;
  for (const auto fh : polyMesh.faces()) {
    std::vector<int64_t> corners;
    for (const auto vh : polyMesh.fv_range(fh)) corners.push_back(vh.idx());
    Rgb rho = kDefaultReflectance;
    if (hasColour && !exactColours.empty()) {
      rho = exactColours[fileFace[fh.idx()]];
    } else if (hasColour) {
      const auto& c = polyMesh.color(fh);
      rho = {c[0], c[1], c[2]};
    }
    std::vector<Vec3> polygon;
    for (int64_t i : corners) polygon.push_back(mesh.vertices[i]);
    if (crossesItself(polygon)) {
      throw InputError(path + ": face " + std::to_string(fileFace[fh.idx()]) +
                       " (counting from 0): its outline crosses itself (a bowtie): it has no "
                       "inside to light; split it into simple polygons");
    }
    // Same as the OBJ reader: the fan for convex polygons, correct for concave ones.
    for (const Triangle& t : added.triangles(triangulatePolygon(polygon), corners)) {
      mesh.triangles.push_back(t);
      mesh.sourceFace.push_back(fileFace[fh.idx()]);
      mesh.reflectance.push_back(rho);
      mesh.emission.push_back(
          withEmission ? Rgb{emitted[0][fh.idx()], emitted[1][fh.idx()], emitted[2][fh.idx()]}
                       : Rgb{0, 0, 0});
      mesh.label.push_back(0);
    }
  }
  added.appendTo(mesh);
}

}  // namespace

Mesh readOpenMeshFile(const std::string& path) {
  const std::string extension = lowerExtension(path);
  const CheckedInput input = checkInput(path, extension);
  const PlyEmission plyEmission = extension == ".ply" ? findPlyEmission(path) : PlyEmission{};
  PolyMesh polyMesh;
  polyMesh.request_face_colors();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceColor;
  const std::vector<std::string> messages =
      readPolyMesh(polyMesh, path, plyEmission, input, options);

  Mesh mesh;
  takeMessages(messages, input.facts, path, mesh);
  const std::vector<int64_t> fileFace =
      fileFaces(input.facts, polyMesh.n_faces(), messages, path, mesh);
  mesh.vertices.reserve(polyMesh.n_vertices());
  for (const auto vh : polyMesh.vertices()) {
    const auto& p = polyMesh.point(vh);
    mesh.vertices.push_back({p[0], p[1], p[2]});
  }
  const bool hasColour = options.face_has_color();
  if (!hasColour) {
    mesh.warnings.push_back(path + ": no face colours; every face gets ρ = 0.5" +
                            (plyEmission.present ? "" : ", E = 0"));
  }
  const std::array<std::vector<double>, 3> emitted = emittedPerFace(polyMesh, plyEmission, path);
  // One label for the whole file, for messages such as the winding warning.
  mesh.labelNames.push_back(std::filesystem::path(path).filename().string());
  appendFaces(polyMesh,
              {fileFace, hasColour, input.facts.faceColours, plyEmission.present, emitted}, path,
              mesh);
  return mesh;
}

}  // namespace radiosity::detail
