// Our own OBJ reader: OpenMesh's drops non-manifold faces (shifting face indices), ignores Ke and
// reports no line numbers.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include "core/error.h"
#include "core/input_file.h"
#include "io/scene/mtl_reader.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

std::string numberProblem(NumberStatus status, std::string_view token) {
  return std::string(status == NumberStatus::kMalformed ? "malformed number '"
                                                        : "number out of range '") +
         std::string(token) + "'";
}

class ObjReader {
 public:
  explicit ObjReader(std::string path) : path_(std::move(path)) {}
  Mesh read();

 private:
  void vertex(const Statement& s);
  void face(const Statement& s);
  int64_t vertexIndex(const Statement& s, std::string_view corner);
  void mtllib(const Statement& s);
  void usemtl(const Statement& s);
  void assignMaterials();
  int32_t currentLabel();

  std::string path_;
  Mesh mesh_;
  MaterialLibrary library_;
  std::vector<std::string> mtlFiles_;
  // A usemtl name becomes a slot; slots are resolved at the end so mtllib may come late.
  std::map<std::string, int> slotOfName_;
  std::vector<std::string> slotName_;
  std::vector<long> slotLine_;  ///< first usemtl line of each slot
  int currentSlot_ = -1;        ///< -1: no usemtl yet
  std::vector<int> triangleSlot_;
  // Labels for messages: material + group (or object) name, numbered as first met.
  std::string group_, object_;
  std::map<std::string, int32_t> labelOfName_;
  int32_t cachedLabel_ = -1;  ///< label of the current (material, group); -1: to be looked up
  int64_t faceCount_ = 0;     ///< every f statement counts, so sourceFace is the OBJ face order
  int64_t facesWithoutMaterial_ = 0;
  std::map<std::string, int64_t> ignored_;  ///< unsupported OBJ keyword → count
  std::vector<Vec3> polygon_;
  std::vector<int64_t> corners_;
  AddedVertices added_;  ///< points triangulation adds inside polygons: after the file's own
};

Mesh ObjReader::read() {
  std::string content;
  if (!readWholeFile(path_, content)) throw InputError(path_ + ": cannot read file");
  StatementReader reader(path_, std::move(content));
  Statement s;
  while (reader.next(s)) {
    const std::string_view keyword = s.tokens[0];
    if (keyword == "v") {
      vertex(s);
    } else if (keyword == "f") {
      face(s);
    } else if (keyword == "usemtl") {
      usemtl(s);
    } else if (keyword == "mtllib") {
      mtllib(s);
    } else if (keyword == "g" || keyword == "o") {
      // Names do not affect radiosity but label the faces in messages.
      (keyword == "g" ? group_ : object_) = std::string(s.rest);
      if (keyword == "o") group_.clear();
      cachedLabel_ = -1;
    } else if (keyword == "vt" || keyword == "vn" || keyword == "s") {
      // Texture coordinates, normals and smoothing groups do not affect radiosity.
    } else {
      ++ignored_[std::string(keyword)];
    }
  }
  assignMaterials();
  added_.appendTo(mesh_);
  mesh_.sourceFiles = mtlFiles_;

  if (!ignored_.empty()) {
    std::string list;
    for (const auto& [keyword, count] : ignored_) {
      list += (list.empty() ? "" : ", ") + keyword + " (" + std::to_string(count) + "×)";
    }
    mesh_.warnings.push_back(path_ + ": ignored unsupported OBJ statements: " + list);
  }
  if (!library_.ignoredKeywords.empty()) {
    std::string files, list;
    for (const auto& f : mtlFiles_) files += (files.empty() ? "" : ", ") + f;
    for (const auto& k : library_.ignoredKeywords) list += (list.empty() ? "" : ", ") + k;
    mesh_.warnings.push_back(files + ": ignored MTL statements (only Kd and Ke are used): " + list);
  }
  if (facesWithoutMaterial_ > 0) {
    mesh_.warnings.push_back(path_ + ": " + std::to_string(facesWithoutMaterial_) +
                             " face(s) without material (no usemtl before them); using ρ = 0.5, "
                             "E = 0");
  }
  return std::move(mesh_);
}

void ObjReader::vertex(const Statement& s) {
  if (s.tokens.size() < 4) throw InputError(path_, s.line, "vertex needs three coordinates");
  Vec3 p;
  for (size_t i = 1; i < s.tokens.size(); ++i) {  // w, or r g b of some writers, is ignored
    double value = 0;
    const NumberStatus status = parseNumber(s.tokens[i], value);
    if (status != NumberStatus::kOk)
      throw InputError(path_, s.line, numberProblem(status, s.tokens[i]));
    if (i > 3) continue;
    if (!std::isfinite(value)) {
      throw InputError(path_, s.line,
                       "vertex coordinate '" + std::string(s.tokens[i]) + "' is not finite");
    }
    if (std::abs(value) > kMaxCoordinate) {
      throw InputError(path_, s.line,
                       "vertex coordinate " + std::string(s.tokens[i]) + " exceeds 1e30");
    }
    p[static_cast<int>(i) - 1] = value;
  }
  mesh_.vertices.push_back(p);
}

/// The position index of one face corner "i", "i/j", "i//k" or "i/j/k" (1-based or negative).
int64_t ObjReader::vertexIndex(const Statement& s, std::string_view corner) {
  std::string_view parts[3];
  int count = 0;
  for (size_t start = 0;; ++count) {
    const size_t slash = corner.find('/', start);
    if (count == 3)
      throw InputError(path_, s.line, "malformed face corner '" + std::string(corner) + "'");
    parts[count] = corner.substr(start, slash == std::string_view::npos ? slash : slash - start);
    if (slash == std::string_view::npos) {
      ++count;
      break;
    }
    start = slash + 1;
  }
  // vt and vn indices are not used, but must still be numbers (an empty vt is the "i//k" form).
  for (int k = 0; k < count; ++k) {
    long long value = 0;
    if (k == 1 && parts[k].empty() && count == 3) continue;
    if (parseInteger(parts[k], value) != NumberStatus::kOk) {
      throw InputError(path_, s.line, "malformed face corner '" + std::string(corner) + "'");
    }
  }
  long long index = 0;
  parseInteger(parts[0], index);
  const auto n = static_cast<long long>(mesh_.vertices.size());
  if (index == 0) throw InputError(path_, s.line, "face index 0 (OBJ indices start at 1)");
  const long long resolved = index > 0 ? index - 1 : n + index;  // negative: relative to the end
  if (resolved < 0 || resolved >= n) {
    throw InputError(path_, s.line,
                     "face index " + std::to_string(index) + " out of range (" + std::to_string(n) +
                         " vertices defined so far)");
  }
  return resolved;
}

void ObjReader::face(const Statement& s) {
  const size_t n = s.tokens.size() - 1;
  if (n < 3) {
    throw InputError(path_, s.line,
                     "face with " + std::to_string(n) + " vertices (at least 3 needed)");
  }
  corners_.clear();
  polygon_.clear();
  for (size_t i = 1; i <= n; ++i) corners_.push_back(vertexIndex(s, s.tokens[i]));
  if (n > 3) {
    // Before anything quadratic in the corners: such a face is refused whatever its size.
    if (const std::optional<int64_t> repeated = repeatedCorner(corners_))
      throw InputError(path_, s.line, repeatedCornerProblem("the face", *repeated + 1));
    for (int64_t c : corners_) polygon_.push_back(mesh_.vertices[c]);
    if (crossesItself(polygon_)) {
      throw InputError(path_, s.line,
                       "the face's outline crosses itself (a bowtie): it has no inside to "
                       "light; split it into simple polygons");
    }
  }
  const int32_t label = currentLabel();
  auto add = [&](const Triangle& t) {
    mesh_.triangles.push_back(t);
    mesh_.sourceFace.push_back(faceCount_);
    triangleSlot_.push_back(currentSlot_);
    mesh_.label.push_back(label);
  };
  if (n == 3) {  // the common case, without the allocations of the polygon path
    add({corners_[0], corners_[1], corners_[2]});
  } else {
    for (const Triangle& t : added_.triangles(triangulatePolygon(polygon_), corners_)) add(t);
  }
  if (currentSlot_ < 0) ++facesWithoutMaterial_;
  ++faceCount_;
}

void ObjReader::mtllib(const Statement& s) {
  if (s.rest.empty()) throw InputError(path_, s.line, "mtllib without a file name");
  const std::filesystem::path folder = std::filesystem::path(path_).parent_path();
  // Several names may follow one mtllib; a single name may contain spaces (Blender writes them
  // unquoted), so the whole rest wins if such a file exists.
  std::vector<std::string_view> names(s.tokens.begin() + 1, s.tokens.end());
  std::error_code ec;
  if (names.size() > 1 && std::filesystem::is_regular_file(folder / s.rest, ec)) names = {s.rest};
  for (std::string_view name : names) {
    const std::string mtlPath = (folder / name).string();
    if (std::find(mtlFiles_.begin(), mtlFiles_.end(), mtlPath) != mtlFiles_.end()) continue;
    std::string content;
    if (const std::string what = notRegularFile(mtlPath); !what.empty() && what != "missing")
      throw InputError(path_, s.line,
                       "mtllib: '" + mtlPath + "' is " + what +
                           ", not an MTL file (only regular files are read)");
    if (!readWholeFile(mtlPath, content)) {
      throw InputError(path_, s.line, "mtllib: cannot read '" + mtlPath + "'");
    }
    mtlFiles_.push_back(mtlPath);
    readMtl(mtlPath, std::move(content), library_);
  }
}

void ObjReader::usemtl(const Statement& s) {
  if (s.rest.empty()) throw InputError(path_, s.line, "usemtl without a material name");
  const auto [it, added] = slotOfName_.emplace(std::string(s.rest), slotName_.size());
  if (added) {
    slotName_.emplace_back(s.rest);
    slotLine_.push_back(s.line);
  }
  currentSlot_ = it->second;
  cachedLabel_ = -1;
}

/// 'material (group name)', 'material (object name)' or 'material' for the faces that follow.
int32_t ObjReader::currentLabel() {
  if (cachedLabel_ >= 0) return cachedLabel_;
  std::string name = currentSlot_ < 0 ? "no material" : slotName_[currentSlot_];
  if (!group_.empty()) {
    name += " (group " + group_ + ")";
  } else if (!object_.empty()) {
    name += " (object " + object_ + ")";
  }
  const auto [it, added] =
      labelOfName_.emplace(name, static_cast<int32_t>(mesh_.labelNames.size()));
  if (added) mesh_.labelNames.push_back(name);
  cachedLabel_ = it->second;
  return cachedLabel_;
}

void ObjReader::assignMaterials() {
  std::vector<const Material*> slotMaterial(slotName_.size());
  for (size_t k = 0; k < slotName_.size(); ++k) {
    const auto it = library_.materials.find(slotName_[k]);
    if (it == library_.materials.end()) {
      std::string where = mtlFiles_.empty() ? " (no mtllib statement)" : " in";
      for (const auto& f : mtlFiles_) where += " " + f;
      throw InputError(path_, slotLine_[k],
                       "usemtl: unknown material '" + slotName_[k] + "'" + where);
    }
    slotMaterial[k] = &it->second;
    if (!it->second.hasKd) {
      mesh_.warnings.push_back(it->second.file + ":" + std::to_string(it->second.line) +
                               ": material '" + slotName_[k] + "' has no Kd; using ρ = 0.5");
    }
  }
  for (int slot : triangleSlot_) {
    mesh_.reflectance.push_back(slot < 0 ? kDefaultReflectance : slotMaterial[slot]->reflectance);
    mesh_.emission.push_back(slot < 0 ? Rgb{0, 0, 0} : slotMaterial[slot]->emission);
  }
}

}  // namespace

Mesh readObj(const std::string& path) { return ObjReader(path).read(); }

}  // namespace radiosity::detail
