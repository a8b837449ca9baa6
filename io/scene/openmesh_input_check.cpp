// The strict walk of PLY and OFF files before OpenMesh reads them (openmesh_input_check.h).
#include "io/scene/openmesh_input_check.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/scene/scene_internal.h"

namespace radiosity::detail {
namespace {

/// The walk of one file: the structure is checked here first, and only a file whose counts are
/// backed by its content is handed to OpenMesh.
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
      if (keyword == "comment" || keyword == "obj_info") {  // obj_info: text, like a comment
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
    if (binary_) checkBinaryByteOrder();
    // The counts on the header line ("OFF 8 6 0", as some writers put them), or on the next.
    std::vector<std::string> counts;
    if (!binary_) {
      std::istringstream words(header.substr(p + 3, header.find('#', p + 3) - (p + 3)));
      for (std::string w; words >> w;) counts.push_back(w);
      if (!counts.empty() &&
          (counts.size() != 3 || !std::isspace(static_cast<unsigned char>(header[p + 3])))) {
        fail("the header line '" + header.substr(0, 40) + "' holds more than " +
             header.substr(0, p + 3) +
             ": after it, only the vertex, face and edge counts may follow, on that line or "
             "the next ('OFF BINARY' for binary)");
      }
      countsOnHeaderLine_ = counts.empty() ? 0 : p + 3;
    }
    if (counts.empty()) counts = {next(), next(), next()};
    const uint64_t vertices = count(counts[0], "vertex count");
    const uint64_t faces = count(counts[1], "face count");
    count(counts[2], "edge count");
    MeshBodyFacts facts;
    facts.faceCount = faces;
    if (!binary_ && countsOnHeaderLine_ == 0 && !line().empty())
      failHere("values after the vertex, face and edge counts");
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
      facts.vertices.push_back({std::stod(values[0]), std::stod(values[1]), std::stod(values[2])});
    }
    std::vector<int64_t> corners;
    for (uint64_t f = 0; f < faces; ++f) {
      const std::string face = "face " + std::to_string(f) + " (counting from 0)";
      const uint64_t cornerCount = count(next(), "face corner count");
      if (cornerCount < 3)
        failHere(face + " has " + std::to_string(cornerCount) + " corner" +
                 (cornerCount == 1 ? "" : "s") + "; a face needs at least 3");
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
    if (binary_ || (text_.find('#') == std::string::npos && countsOnHeaderLine_ == 0)) return {};
    std::string out = text_;
    // OpenMesh takes the whole first line for the header: the counts go to a line of their own.
    if (countsOnHeaderLine_ > 0) out[countsOnHeaderLine_] = '\n';
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
    throw InputError(path_ + ": " + problem + " (checked before reading with OpenMesh)" +
                     (binary_ ? kBinaryOffLayout : ""));
  }
  /// Binary OFF as OpenMesh reads it, which is not Geomview's (big-endian, with a colour count
  /// after each face's indices): a file in that layout is told so, not given a count from
  /// bytes read the wrong way round.
  static constexpr const char* kBinaryOffLayout =
      "; binary OFF is read as OpenMesh writes it: 32-bit little-endian values, nothing after a "
      "face's vertex indices (Geomview's big-endian binary OFF, with a colour count per face, "
      "is not read: convert it to text OFF or to PLY)";
  void checkBinaryByteOrder() {
    const size_t start = pos_;
    const uint64_t little = std::stoull(next());
    pos_ = start;
    if (little <= text_.size() || text_.size() - pos_ < 4) return;
    uint32_t big = 0;
    for (int k = 0; k < 4; ++k) big = big << 8 | static_cast<unsigned char>(text_[pos_ + k]);
    if (big <= text_.size())
      fail("binary OFF in big-endian byte order (its vertex count reads " + std::to_string(big) +
           " that way, " + std::to_string(little) + " little-endian)");
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
  bool comments_ = false;          ///< text OFF: '#' starts a comment
  size_t countsOnHeaderLine_ = 0;  ///< where the counts begin on the header line; 0: not there
  size_t wordStart_ = 0;
};

}  // namespace

void checkPlyStructure(const std::string& path, const std::string& content) {
  OpenMeshInputCheck(path, content).checkPly();
}

OffFile checkOffFile(const std::string& path, const std::string& content) {
  OpenMeshInputCheck check(path, content);
  OffFile off;
  off.facts = check.checkOff();
  off.withoutComments = check.offWithoutComments();
  return off;
}

}  // namespace radiosity::detail
