// PLY and OFF through OpenMesh. Its types stay in this file.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "io/core/error.h"
#include "io/scene/ply_header.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

struct SceneTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;  // keep double coordinates where the file has them
  using Color = OpenMesh::Vec3f;  // OpenMesh scales byte colours to [0, 1] for float colours
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<SceneTraits>;

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
bool readWithOpenMesh(PolyMesh& polyMesh, const std::string& path, const PlyEmission& emission,
                      const std::vector<Vec3>& exact, OpenMesh::IO::Options& options) {
  if (!emission.present) return readMeshGuarded(polyMesh, path, exact, options);
  options += OpenMesh::IO::Options::Custom;
  if (!emission.needsRetyping) return readMeshGuarded(polyMesh, path, exact, options);
  std::string content;
  if (!readWholeFile(path, content)) throw InputError(path + ": cannot read file");
  std::istringstream in(retypeEightBitCustomProperties(path, content), std::ios::binary);
  return readMeshGuarded(polyMesh, in, ".ply", exact, options);
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

/// Routes OpenMesh's diagnostics (omerr/omlog, and a few direct writes to std::cerr) into a
/// string while alive, so that library code prints nothing and the caller sees them as warnings.
/// omerr and omlog write to std::cerr and std::clog, so redirecting those two catches all; their
/// connect()/disconnect() are not used because disconnect() leaks the target (OpenMesh 9.0).
class CaptureOpenMeshMessages {
 public:
  CaptureOpenMeshMessages() {
    ::omerr().flush();
    ::omlog().flush();
    oldCerr_ = std::cerr.rdbuf(text_.rdbuf());
    oldClog_ = std::clog.rdbuf(text_.rdbuf());
  }
  ~CaptureOpenMeshMessages() {
    ::omerr().flush();
    ::omlog().flush();
    std::cerr.rdbuf(oldCerr_);
    std::clog.rdbuf(oldClog_);
  }
  std::vector<std::string> lines() {
    ::omerr().flush();
    ::omlog().flush();
    std::vector<std::string> out;
    std::istringstream in(text_.str());
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) out.push_back(line);
    }
    return out;
  }

 private:
  std::ostringstream text_;
  std::streambuf* oldCerr_ = nullptr;
  std::streambuf* oldClog_ = nullptr;
};

/// OpenMesh 9.0 trusts what a file says: a PLY header without end_header, or with a bad count,
/// makes it loop forever; a property before any element reads past a vector; a huge element,
/// face or list count makes it reserve or loop without bound. So the structure is walked here
/// first, and only a file whose counts are backed by its content is handed to OpenMesh.
class OpenMeshInputCheck {
 public:
  OpenMeshInputCheck(const std::string& path, const std::string& content)
      : path_(path), text_(content) {}

  void checkPly() {
    const std::string magic = line();
    if (magic != "ply" && magic != "PLY") fail("not a PLY file (first line must be 'ply')");
    const std::string format = word();
    const std::string type = word();
    if (format != "format" ||
        (type != "ascii" && type != "binary_little_endian" && type != "binary_big_endian") ||
        !isNumber(word())) {
      fail("PLY header: expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
    }
    bool inElement = false;
    for (std::string keyword = word(); keyword != "end_header"; keyword = word()) {
      if (keyword.empty()) fail("PLY header without end_header");
      if (keyword == "comment") {
        line();
      } else if (keyword == "element") {
        word();
        count(word(), "element count");
        inElement = true;
      } else if (keyword == "property" && inElement) {
        const std::string first = word(), second = word();
        if (first == "list") {
          // Only byte-sized list lengths: OpenMesh sizes a face by the count it reads.
          if (second != "uchar" && second != "uint8")
            fail("PLY header: list count type '" + second + "' (supported: uchar, uint8)");
          const std::string entry = word();
          if (!isPlyType(entry)) fail("PLY header: unknown property type '" + entry + "'");
          if (word().empty()) fail("PLY header: property without a name");
        } else if (!isPlyType(first) && !isPlyType(second)) {  // "TYPE NAME" or "NAME TYPE"
          fail("PLY header: property '" + first + " " + second + "' has no known type");
        }
      } else {
        fail("PLY header: unexpected '" + keyword + "'");
      }
    }
  }

  MeshBodyFacts checkOff() {
    const std::string header = line();
    const bool texture = header.starts_with("ST");
    size_t p = texture ? 2 : 0;
    const bool colour = header.compare(p, 1, "C") == 0;
    p += colour;
    const bool normal = header.compare(p, 1, "N") == 0;
    p += normal;
    if (header.compare(p, 1, "4") == 0 || header.compare(p, 1, "n") == 0)
      fail("OFF: 4OFF and nOFF (other than 3 dimensions) are not supported");
    if (header.compare(p, 3, "OFF") != 0) fail("not an OFF file (first line must be [C][N]OFF)");
    binary_ = header.size() >= p + 10 && header.compare(p + 4, 6, "BINARY") == 0;  // as OpenMesh
    comments_ = !binary_;  // '#' to the end of the line
    const uint64_t vertices = count(next(), "vertex count");
    const uint64_t faces = count(next(), "face count");
    count(next(), "edge count");
    MeshBodyFacts facts;
    facts.faceCount = faces;
    if (!binary_ && !line().empty()) failHere("values after the vertex, face and edge counts");
    for (uint64_t v = 0; v < vertices; ++v) {
      if (binary_) {  // 32-bit floats: OpenMesh keeps them exactly
        for (int k = 0; k < 3 + 3 * normal + 3 * colour + 2 * texture; ++k) next();
        continue;
      }
      // One vertex a line: OpenMesh reads x y z [normal] and takes the rest of the line as its
      // colour and texture coordinates, so values missing here would be taken from the next.
      const std::vector<std::string> values = lineValues();
      const size_t needed = 3 + 3 * normal + 2 * texture;
      const bool fits = values.size() == needed ||
                        (colour && values.size() > needed && values.size() <= needed + 4);
      if (!fits) {
        failHere("vertex " + std::to_string(v) + " (counting from 0) has " +
                 std::to_string(values.size()) + " values where " + header.substr(0, p + 3) +
                 " needs " + std::to_string(needed) +
                 (colour ? " and at most 4 colour values"
                         : (values.size() > needed ? "; colours need a COFF header" : "")));
      }
      for (const std::string& value : values) number(value);
      facts.vertices.push_back(
          {std::stod(values[0]), std::stod(values[1]), std::stod(values[2])});
    }
    std::vector<int64_t> corners;
    for (uint64_t f = 0; f < faces; ++f) {
      const std::string face = "face " + std::to_string(f) + " (counting from 0)";
      const uint64_t cornerCount = count(next(), "face corner count");
      if (cornerCount < 3)
        failHere(face + " has " + std::to_string(cornerCount) + " corner" + (cornerCount == 1 ? "" : "s") +
                 "; a face needs at least 3");
      corners.clear();
      for (uint64_t k = 0; k < cornerCount; ++k) {
        const uint64_t index = count(next(), "vertex index");
        if (index >= vertices) {
          failHere(face + ": vertex index " + std::to_string(index) +
                   " is out of range (the file has " + std::to_string(vertices) + " vertices)");
        }
        corners.push_back(static_cast<int64_t>(index));
      }
      if (const std::optional<int64_t> repeated = repeatedCorner(corners)) {
        if (corners.size() > 3) failHere(repeatedCornerProblem(face, *repeated));
        if (facts.droppedFaces.empty()) facts.firstDroppedLine = binary_ ? 0 : lineHere();
        facts.droppedFaces.push_back(f);
      }
      if (binary_) {
        for (int k = 0; k < 3 * colour; ++k) next();
      } else if (colour) {
        line();
      } else if (!line().empty()) {  // OpenMesh would read these as the next face
        failHere(face + " has values after its " + std::to_string(cornerCount) +
                 " vertex indices; face colours in OFF need a COFF header");
      }
    }
    if (!binary_ && !word().empty()) {
      failHere("more faces than the header declares (" + std::to_string(faces) + ")");
    }
    return facts;
  }

  /// The text of a text OFF file with its '#' comments blanked out (same lines, same layout),
  /// for OpenMesh, which does not know comments. Empty if the file has none.
  std::string offWithoutComments() const {
    if (binary_ || text_.find('#') == std::string::npos) return {};
    std::string out = text_;
    bool inComment = false;
    for (char& c : out) {
      if (c == '\n') {
        inComment = false;
      } else if (c == '#' || inComment) {
        inComment = true;
        if (c != '\r') c = ' ';
      }
    }
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(path_ + ": " + problem + " (checked before reading with OpenMesh)");
  }
  /// Fails at the line of the last word read (text files), else as fail().
  [[noreturn]] void failHere(const std::string& problem) const {
    if (binary_) fail(problem);
    throw InputError(path_, lineHere(), problem);
  }
  /// The line of the last word read (1-based).
  long lineHere() const {
    return 1 + static_cast<long>(std::count(text_.begin(), text_.begin() + wordStart_, '\n'));
  }
  /// The words of the next line that has any (comments taken out); fails at the end.
  std::vector<std::string> lineValues() {
    while (pos_ < text_.size()) {
      const size_t start = pos_;
      std::istringstream words(line());
      std::vector<std::string> values;
      for (std::string w; words >> w;) values.push_back(w);
      if (values.empty()) continue;
      wordStart_ = text_.find_first_not_of(" \t\r\v\f", start);
      return values;
    }
    fail("OFF file ends early (fewer vertices or faces than its header says)");
  }

  /// The rest of the current line, without its end.
  std::string line() {
    const size_t end = std::min(text_.find('\n', pos_), text_.size());
    last_ = text_.substr(pos_, end - pos_);
    if (comments_) last_ = last_.substr(0, last_.find('#'));
    pos_ = std::min(end + 1, text_.size());
    while (!last_.empty() && std::isspace(static_cast<unsigned char>(last_.back())))
      last_.pop_back();
    return last_;
  }
  /// The next whitespace-separated word ("" at the end), as `istream >> string` reads it.
  std::string word() {
    for (;;) {
      while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      if (!comments_ || pos_ >= text_.size() || text_[pos_] != '#') break;
      pos_ = std::min(text_.find('\n', pos_), text_.size());
    }
    const size_t start = pos_;
    wordStart_ = start;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           !(comments_ && text_[pos_] == '#'))
      ++pos_;
    return text_.substr(start, pos_ - start);
  }
  /// The next value of an OFF body: a word, or 4 bytes (OpenMesh reads binary OFF as LSB).
  std::string next() {
    if (!binary_) {
      std::string w = word();
      if (w.empty()) fail("OFF file ends early (fewer vertices or faces than its header says)");
      return w;
    }
    if (text_.size() - pos_ < 4) fail("binary OFF file ends early");
    uint32_t value = 0;
    for (int k = 3; k >= 0; --k) value = value << 8 | static_cast<unsigned char>(text_[pos_ + k]);
    pos_ += 4;
    return std::to_string(value);
  }
  uint64_t count(const std::string& token, const char* what) {
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (token.empty() || ec != std::errc() || end != token.data() + token.size())
      fail(std::string(what) + " '" + token + "' is not a non-negative integer");
    // Every element, corner and index takes at least a byte of the file.
    if (value > text_.size()) fail(std::string(what) + " " + token + " exceeds the file's size");
    return value;
  }
  void number(const std::string& token) {
    if (!binary_ && !isNumber(token)) fail("OFF: malformed number '" + token + "'");
  }
  static bool isNumber(const std::string& token) {
    double value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return !token.empty() && ec == std::errc() && end == token.data() + token.size() &&
           std::isfinite(value) && std::abs(value) < 3e38;  // also a float: OpenMesh reads those
  }
  static bool isPlyType(const std::string& t) {
    for (const char* known :
         {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
          "int16", "uint16", "int32", "uint32", "float32", "float64"}) {
      if (t == known) return true;
    }
    return false;
  }

  const std::string& path_;
  const std::string& text_;
  size_t pos_ = 0;
  std::string last_;
  bool binary_ = false;
  bool comments_ = false;  ///< text OFF: '#' starts a comment
  size_t wordStart_ = 0;
};

}  // namespace

Mesh readOpenMeshFile(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string offText;  // a text OFF file with comments, blanked for OpenMesh
  MeshBodyFacts facts;
  {
    std::string content;
    if (!readWholeFile(path, content)) throw InputError(path + ": cannot read file");
    OpenMeshInputCheck check(path, content);
    if (extension == ".ply") {
      check.checkPly();
      facts = checkPlyBody(path, content, scanPlyHeader(path, content));
    }
    if (extension == ".off") {
      facts = check.checkOff();
      offText = check.offWithoutComments();
    }
  }
  const PlyEmission plyEmission = extension == ".ply" ? findPlyEmission(path) : PlyEmission{};
  PolyMesh polyMesh;
  polyMesh.request_face_colors();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceColor;
  std::vector<std::string> messages;
  {
    CaptureOpenMeshMessages capture;
    const bool ok = offText.empty()
                         ? readWithOpenMesh(polyMesh, path, plyEmission, facts.vertices, options)
                         : readOffText(polyMesh, path, offText, facts.vertices, options);
    messages = capture.lines();
    if (!ok) {
      std::string detail;
      for (const auto& m : messages) detail += "; " + m;
      throw InputError(path + ": not a readable mesh file (OpenMesh reader failed" + detail + ")");
    }
  }
  Mesh mesh;
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
  if (polyMesh.n_faces() + facts.droppedFaces.size() != facts.faceCount) {
    std::string detail;
    for (const auto& m : messages) detail += "; " + m;
    throw InputError(path + ": OpenMesh read " + std::to_string(polyMesh.n_faces()) + " of its " +
                     std::to_string(facts.faceCount) + " faces" + detail);
  }
  // OpenMesh's face k is the file's k-th face not dropped.
  std::vector<int64_t> fileFace;
  fileFace.reserve(polyMesh.n_faces());
  for (int64_t face = 0, skipped = 0; fileFace.size() < polyMesh.n_faces(); ++face) {
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
  std::array<std::vector<double>, 3> emitted;
  if (plyEmission.present) {
    for (int c = 0; c < 3; ++c) {
      emitted[c] = faceValues(polyMesh, plyEmission.names[c], plyEmission.scale[c]);
      if (emitted[c].size() != polyMesh.n_faces()) {
        throw InputError(path + ": OpenMesh did not read the face property '" +
                         plyEmission.names[c] + "' (it must come after vertex_indices)");
      }
    }
  }
  // One label for the whole file, for messages such as the winding warning.
  mesh.labelNames.push_back(std::filesystem::path(path).filename().string());
  for (const auto fh : polyMesh.faces()) {
    std::vector<int64_t> corners;
    for (const auto vh : polyMesh.fv_range(fh)) corners.push_back(vh.idx());
    Rgb rho = kDefaultReflectance;
    if (hasColour) {
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
    for (const auto& t : triangulatePolygon(polygon)) {
      mesh.triangles.push_back({corners[t[0]], corners[t[1]], corners[t[2]]});
      mesh.sourceFace.push_back(fileFace[fh.idx()]);
      mesh.reflectance.push_back(rho);
      mesh.emission.push_back(plyEmission.present ? Rgb{emitted[0][fh.idx()], emitted[1][fh.idx()],
                                                        emitted[2][fh.idx()]}
                                                  : Rgb{0, 0, 0});
      mesh.label.push_back(0);
    }
  }
  return mesh;
}

}  // namespace radiosity::detail
