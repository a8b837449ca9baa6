// A strict walk of a PLY body against its header, before OpenMesh (which trusts the file) reads
// it: counts, value counts per line, number syntax and type ranges, vertex indices.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>

#include "core/error.h"
#include "io/scene/ply_header.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

struct PlyType {
  size_t bytes = 0;
  bool real = false;  ///< float or double
  double min = 0, max = 0;
};

PlyType plyType(const std::string& t) {
  if (t == "char" || t == "int8") return {1, false, -128, 127};
  if (t == "uchar" || t == "uint8") return {1, false, 0, 255};
  if (t == "short" || t == "int16") return {2, false, -32768, 32767};
  if (t == "ushort" || t == "uint16") return {2, false, 0, 65535};
  if (t == "int" || t == "int32") return {4, false, -2147483648.0, 2147483647.0};
  if (t == "uint" || t == "uint32") return {4, false, 0, 4294967295.0};
  if (t == "float" || t == "float32") {
    return {4, true, -std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  }
  if (t == "double" || t == "float64") {
    return {8, true, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  }
  return {};
}

bool isIndexList(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.isList && (p.name == "vertex_indices" || p.name == "vertex_index");
}

uint64_t vertexCount(const PlyHeader& header) {
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") return e.count;
  }
  return 0;
}

/// "face 3 (counting from 0)"
std::string which(const PlyElement& e, uint64_t index) {
  return e.name + " " + std::to_string(index) + " (counting from 0)";
}

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/// Which coordinate (0, 1, 2) a vertex property holds, -1 for none.
int coordinateOf(const PlyElement& e, const PlyProperty& p) {
  if (e.name != "vertex" || p.isList) return -1;
  if (p.name == "x") return 0;
  if (p.name == "y") return 1;
  if (p.name == "z") return 2;
  return -1;
}

/// Which channel (0, 1, 2) a face colour property of a real type holds, -1 for none: the
/// colours OpenMesh reads as ρ (it reads no diffuse_* face properties).
int realColourChannel(const PlyElement& e, const PlyProperty& p) {
  if (e.name != "face" || p.isList || !plyType(p.type).real) return -1;
  if (p.name == "red") return 0;
  if (p.name == "green") return 1;
  if (p.name == "blue") return 2;
  return -1;
}

/// The problem with a face colour of a real type outside [0, 1] ("" if none): OpenMesh takes
/// such a colour as a fraction and stores it as a byte, ×255 modulo 256 (200 became ρ = 0.22),
/// so a file in the 0–255 convention would be read wrong without a word.
std::string colourProblem(const PlyElement& e, uint64_t index, const PlyProperty& p, double v) {
  if (realColourChannel(e, p) < 0 || (v >= 0 && v <= 1)) return {};
  char value[32];
  std::snprintf(value, sizeof value, "%g", v);
  return which(e, index) + ": colour '" + p.name + "' is " + value + ", outside [0, 1]: a " +
         p.type + " colour is a fraction (0–255 is for uchar colours)";
}

/// Records a vertex coordinate or a real face colour and checks a face's corners once its list is
/// read.
class BodyFacts {
 public:
  void coordinate(const PlyElement& e, uint64_t index, const PlyProperty& p, double v) {
    if (const int channel = realColourChannel(e, p); channel >= 0) {
      if (index >= facts_.faceColours.size()) facts_.faceColours.resize(index + 1);
      facts_.faceColours[index][channel] = v;
      realChannels_ |= 1 << channel;
    }
    const int axis = coordinateOf(e, p);
    if (axis < 0) return;
    // Grown as the vertices come: a header may declare more than the file holds.
    if (index >= facts_.vertices.size()) facts_.vertices.resize(index + 1);
    if (axis == 0) facts_.vertices[index].x = v;
    if (axis == 1) facts_.vertices[index].y = v;
    if (axis == 2) facts_.vertices[index].z = v;
  }
  /// The problem with the face's corners ("" if none); a triangle naming a vertex twice is
  /// recorded as dropped (`line`: where, 0 in a binary file).
  std::string face(const std::string& name, uint64_t index, const std::vector<int64_t>& corners,
                   long line) {
    const std::optional<int64_t> repeated = repeatedCorner(corners);
    if (!repeated) return {};
    if (corners.size() > 3) return repeatedCornerProblem(name, *repeated);
    if (facts_.droppedFaces.empty()) facts_.firstDroppedLine = line;
    facts_.droppedFaces.push_back(index);
    return {};
  }
  MeshBodyFacts take() {
    if (realChannels_ != 7) facts_.faceColours.clear();  // some channels are bytes: OpenMesh's
    return std::move(facts_);
  }

 private:
  MeshBodyFacts facts_;
  int realChannels_ = 0;  ///< bit c: channel c is a float or double face property
};

std::string plural(uint64_t n, const std::string& what) {
  const std::string many = what == "vertex" ? "vertices" : what + "s";
  return std::to_string(n) + " " + (n == 1 ? what : many);
}

/// What a walk of a PLY body works on: the file, its header, where the walk is, and the facts
/// it gathers; shared by the ASCII and the binary walk.
class BodyWalk {
 protected:
  BodyWalk(const std::string& path, const std::string& content, const PlyHeader& header)
      : path_(path),
        text_(content),
        header_(header),
        pos_(header.headerEnd),
        vertices_(vertexCount(header)) {}

  /// Whether `v`, read from an index list, names one of the file's vertices.
  bool isVertexIndex(double v) const {
    return v >= 0 && v < static_cast<double>(vertices_) && v == std::floor(v);
  }

  /// A bad index read as a number, for the message: a whole number as such, anything else (a
  /// fraction, NaN, 1e30 from a float list: no integer holds it) as %g.
  static std::string indexText(double v) {
    if (std::abs(v) < 0x1p53 && v == std::floor(v)) return std::to_string(static_cast<int64_t>(v));
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
  }

  const std::string& path_;
  const std::string& text_;
  const PlyHeader& header_;
  size_t pos_;
  uint64_t vertices_;
  BodyFacts facts_;
};

/// The body of an ASCII PLY file, line by line.
class AsciiBody : BodyWalk {
 public:
  AsciiBody(const std::string& path, const std::string& content, const PlyHeader& header)
      : BodyWalk(path, content, header), line_(header.headerLines) {}

  MeshBodyFacts check() {
    for (const PlyElement& e : header_.elements) {
      for (uint64_t i = 0; i < e.count; ++i) {
        if (!nextLine()) {
          throw InputError(path_, line_ + 1,
                           "the file ends after " + std::to_string(i) + " of the " +
                               plural(e.count, e.name) + " its header declares (line " +
                               std::to_string(e.line) + ")");
        }
        checkElement(e, i);
      }
    }
    if (nextLine()) {
      std::string declared;
      for (const PlyElement& e : header_.elements)
        declared += (declared.empty() ? "" : ", ") + plural(e.count, e.name);
      throw InputError(path_, line_,
                       "more lines than the header declares (" +
                           (declared.empty() ? std::string("no elements") : declared) + ")");
    }
    return facts_.take();
  }

 private:
  bool nextLine() {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      const std::string_view line(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      tokens_.clear();
      for (size_t k = 0; k < line.size();) {
        while (k < line.size() && isBlank(line[k])) ++k;
        const size_t start = k;
        while (k < line.size() && !isBlank(line[k])) ++k;
        if (k > start) tokens_.push_back(line.substr(start, k - start));
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }

  void checkElement(const PlyElement& e, uint64_t index) {
    size_t k = 0;
    auto take = [&](const PlyProperty& p) -> std::string_view {
      if (k >= tokens_.size()) {
        throw InputError(path_, line_,
                         which(e, index) + " has only " + plural(tokens_.size(), "value") +
                             ": property '" + p.name + "' (line " + std::to_string(p.line) +
                             ") is missing");
      }
      return tokens_[k++];
    };
    for (const PlyProperty& p : e.properties) {
      if (!p.isList) {
        const double v = value(take(p), p.type, e, index, p);
        facts_.coordinate(e, index, p, v);
        if (const std::string problem = colourProblem(e, index, p, v); !problem.empty())
          throw InputError(path_, line_, problem);
        continue;
      }
      const double n = value(take(p), p.countType, e, index, p);
      if (isIndexList(e, p) && n < 3) {
        throw InputError(path_, line_,
                         which(e, index) + " has " + plural(static_cast<uint64_t>(n), "corner") +
                             "; a face needs at least 3");
      }
      corners_.clear();
      for (uint64_t j = 0; j < static_cast<uint64_t>(n); ++j) {
        const std::string_view entry = take(p);
        const double v = value(entry, p.type, e, index, p);
        if (isIndexList(e, p) && !isVertexIndex(v)) {
          throw InputError(path_, line_,
                           which(e, index) + ": vertex index " + std::string(entry) +
                               " is out of range (the file has " + plural(vertices_, "vertex") +
                               ")");
        }
        // Only an index list's values are corners (checked above to be whole and in range);
        // another list's may be any real, which no integer need hold.
        if (isIndexList(e, p)) corners_.push_back(static_cast<int64_t>(v));
      }
      if (isIndexList(e, p)) {
        const std::string problem = facts_.face(which(e, index), index, corners_, line_);
        if (!problem.empty()) throw InputError(path_, line_, problem);
      }
    }
    if (k != tokens_.size()) {
      throw InputError(path_, line_,
                       which(e, index) + " has " + plural(tokens_.size(), "value") +
                           " where its properties need " + std::to_string(k) +
                           " (one line per element)");
    }
  }

  double value(std::string_view token, const std::string& typeName, const PlyElement& e,
               uint64_t index, const PlyProperty& p) const {
    const PlyType type = plyType(typeName);
    // Built only for a message: this runs for every value of the file.
    const auto where = [&] { return " (property '" + p.name + "' of " + which(e, index) + ")"; };
    const auto quoted = [&] {
      std::string q = "'";
      return q.append(token).append("'");
    };
    double v = 0;
    if (type.real) {
      const NumberStatus status = parseNumber(token, v);
      if (status == NumberStatus::kMalformed) {
        throw InputError(path_, line_, quoted() + " is not a number" + where());
      }
      if (status == NumberStatus::kOk && !std::isfinite(v)) {
        throw InputError(path_, line_, quoted() + " is not a finite number" + where());
      }
      if (status == NumberStatus::kOutOfRange || v < type.min || v > type.max) {
        throw InputError(path_, line_,
                         quoted() + " is out of the range of type '" + typeName + "'" + where());
      }
      return v;
    }
    long long i = 0;
    const NumberStatus status = parseInteger(token, i);
    if (status == NumberStatus::kMalformed) {
      const bool number = parseNumber(token, v) != NumberStatus::kMalformed;
      throw InputError(path_, line_,
                       quoted() +
                           (number ? " is not an integer, as type '" + typeName + "' needs"
                                   : std::string(" is not a number")) +
                           where());
    }
    if (status == NumberStatus::kOutOfRange || static_cast<double>(i) < type.min ||
        static_cast<double>(i) > type.max) {
      throw InputError(path_, line_,
                       quoted() + " is out of the range of type '" + typeName + "' (" +
                           std::to_string(static_cast<long long>(type.min)) + " to " +
                           std::to_string(static_cast<long long>(type.max)) + ")" + where());
    }
    return static_cast<double>(i);
  }

  long line_;
  std::vector<std::string_view> tokens_;
  std::vector<int64_t> corners_;
};

/// The body of a binary PLY file, element by element.
class BinaryBody : BodyWalk {
 public:
  BinaryBody(const std::string& path, const std::string& content, const PlyHeader& header)
      : BodyWalk(path, content, header) {}

  MeshBodyFacts check() {
    for (const PlyElement& e : header_.elements) {
      for (uint64_t i = 0; i < e.count; ++i) {
        for (const PlyProperty& p : e.properties) {
          if (!p.isList) {
            const double v = read(p.type, e, i, p);
            facts_.coordinate(e, i, p, v);
            if (const std::string problem = colourProblem(e, i, p, v); !problem.empty())
              throw InputError(path_ + ": " + problem);
            continue;
          }
          const double n = read(p.countType, e, i, p);
          if (n < 0) fail(e, i, "list '" + p.name + "' has a negative count");
          if (isIndexList(e, p) && n < 3) {
            fail(e, i,
                 "has " + plural(static_cast<uint64_t>(n), "corner") + "; a face needs at least 3");
          }
          if (!isIndexList(e, p) && !plyType(p.type).real) {  // skip, only the size matters
            const size_t bytes = static_cast<size_t>(n) * plyType(p.type).bytes;
            if (text_.size() - pos_ < bytes) endsEarly(e, i);
            pos_ += bytes;
            continue;
          }
          std::vector<int64_t> corners;
          for (uint64_t j = 0; j < static_cast<uint64_t>(n); ++j) {
            const double v = read(p.type, e, i, p);
            if (isIndexList(e, p) && !isVertexIndex(v)) {
              fail(e, i,
                   "vertex index " + indexText(v) + " is out of range (the file has " +
                       plural(vertices_, "vertex") + ")");
            }
            if (isIndexList(e, p)) corners.push_back(static_cast<int64_t>(v));  // as the ASCII walk
          }
          if (isIndexList(e, p)) {
            const std::string problem = facts_.face(which(e, i), i, corners, 0);
            if (!problem.empty()) throw InputError(path_ + ": " + problem);
          }
        }
      }
    }
    if (pos_ != text_.size()) {
      throw InputError(path_ + ": " + plural(text_.size() - pos_, "byte") +
                       " after the last element: the binary body is longer than its header "
                       "declares");
    }
    return facts_.take();
  }

 private:
  [[noreturn]] void fail(const PlyElement& e, uint64_t index, const std::string& problem) const {
    throw InputError(path_ + ": " + which(e, index) + ": " + problem);
  }
  [[noreturn]] void endsEarly(const PlyElement& e, uint64_t index) const {
    fail(e, index,
         "the file ends inside it (the header declares " + plural(e.count, e.name) +
             "): the binary body is shorter than its header declares");
  }

  double read(const std::string& typeName, const PlyElement& e, uint64_t index,
              const PlyProperty& p) {
    const PlyType type = plyType(typeName);
    if (text_.size() - pos_ < type.bytes) endsEarly(e, index);
    unsigned char b[8];
    for (size_t k = 0; k < type.bytes; ++k) {
      b[header_.bigEndian ? type.bytes - 1 - k : k] =
          static_cast<unsigned char>(text_[pos_ + k]);  // b is little-endian
    }
    pos_ += type.bytes;
    uint64_t bits = 0;
    for (size_t k = type.bytes; k-- > 0;) bits = bits << 8 | b[k];
    double v = 0;
    if (type.real) {
      if (type.bytes == 4) {
        float f;
        const auto u = static_cast<uint32_t>(bits);
        std::memcpy(&f, &u, 4);
        v = f;
      } else {
        std::memcpy(&v, &bits, 8);
      }
      if (!std::isfinite(v)) fail(e, index, "property '" + p.name + "' is not a finite number");
    } else if (type.min < 0) {  // sign-extend
      const int shift = 64 - static_cast<int>(8 * type.bytes);
      v = static_cast<double>(static_cast<int64_t>(bits << shift) >> shift);
    } else {
      v = static_cast<double>(bits);
    }
    return v;
  }
};

}  // namespace

MeshBodyFacts checkPlyBody(const std::string& path, const std::string& content,
                           const PlyHeader& header) {
  for (const PlyElement& e : header.elements) {
    for (const PlyProperty& p : e.properties) {
      if (plyType(p.type).bytes == 0) {
        throw InputError(path, p.line, "unknown property type '" + p.type + "'");
      }
      if (p.isList && (plyType(p.countType).bytes == 0 || plyType(p.countType).real)) {
        throw InputError(path, p.line,
                         "list count type '" + p.countType + "' is not an integer type");
      }
    }
  }
  MeshBodyFacts facts = header.ascii ? AsciiBody(path, content, header).check()
                                     : BinaryBody(path, content, header).check();
  for (const PlyElement& e : header.elements)
    if (e.name == "face") facts.faceCount = e.count;
  return facts;
}

}  // namespace radiosity::detail
