// The strict walk of STL files before OpenMesh reads them (stl_structure.h).
#include "io/scene/stl_structure.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <unordered_map>

#include "core/error.h"
#include "core/mesh.h"
#include "core/shown_text.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

constexpr uint64_t kHeaderBytes = 84;  // 80 bytes of anything, then the facet count
constexpr uint64_t kFacetBytes = 50;   // normal, 3 corners (12 floats), 2 attribute bytes

/// A corner's float coordinates as OpenMesh compares them (sameStlCoordinate), as bits.
struct CornerKey {
  std::array<uint32_t, 3> bits;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  size_t operator()(const CornerKey& key) const {
    uint64_t h = key.bits[0];
    h = h * 0x9E3779B97F4A7C15ull ^ key.bits[1];
    h = h * 0x9E3779B97F4A7C15ull ^ key.bits[2];
    return static_cast<size_t>(h ^ (h >> 31));
  }
};

uint32_t keyBits(float f) { return std::bit_cast<uint32_t>(std::abs(f) < FLT_MIN ? 0.0f : f); }

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

bool isKeyword(std::string_view word, std::string_view keyword) {
  if (word.size() != keyword.size()) return false;
  for (size_t i = 0; i < word.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(word[i])) != keyword[i]) return false;
  }
  return true;
}

uint32_t littleEndian32(const char* p) {
  uint32_t value = 0;
  for (int k = 3; k >= 0; --k) value = value << 8 | static_cast<unsigned char>(p[k]);
  return value;
}

/// "1e31" as the message shows it: the file's text for ASCII, the value for binary.
std::string shownValue(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

/// The walk of one file.
class StlWalk {
 public:
  StlWalk(const std::string& path, const std::string& content) : path_(path), text_(content) {}

  StlFile walk() {
    if (text_.size() >= kHeaderBytes) {
      declaredFacets_ = littleEndian32(text_.data() + 80);
      if (text_.size() == kHeaderBytes + kFacetBytes * declaredFacets_) {
        walkBinary();
        return std::move(stl_);
      }
    }
    walkAscii();
    return std::move(stl_);
  }

 private:
  struct Token {
    std::string_view text;  ///< empty at the end of the file
    long line = 0;          ///< 1-based; at the end, the line of the last word
  };

  // --- binary -------------------------------------------------------------------------------

  void walkBinary() {
    stl_.binary = true;
    stl_.solidNames = {""};
    if (declaredFacets_ == 0) fail("binary STL with no facets (its facet count at byte 80 is 0)");
    stl_.facets.reserve(declaredFacets_);
    stl_.facetSolid.reserve(declaredFacets_);
    for (uint64_t f = 0; f < declaredFacets_; ++f) {
      // The normal (the first 12 bytes) is not looked at: the winding says which side is lit.
      const char* corner = text_.data() + kHeaderBytes + kFacetBytes * f + 12;
      std::array<int64_t, 3> corners{};
      for (int c = 0; c < 3; ++c, corner += 12) {
        std::array<float, 3> value{};
        Vec3 exact;
        for (int k = 0; k < 3; ++k) {
          value[k] = std::bit_cast<float>(littleEndian32(corner + 4 * k));
          exact[k] = value[k];
          if (!std::isfinite(exact[k]) || std::abs(exact[k]) > kMaxCoordinate) {
            fail(std::string("facet ")
                     .append(std::to_string(f))
                     .append(" (counting from 0), corner ")
                     .append(std::to_string(c + 1))
                     .append(" of 3: coordinate ")
                     .append(shownValue(exact[k]))
                     .append(" (coordinates must be finite, |x| ≤ 1e30)"));
          }
        }
        corners[c] = cornerVertex(value, exact, 0, f);
      }
      facet(corners, 0, 0);
    }
  }

  // --- ASCII --------------------------------------------------------------------------------

  void walkAscii() {
    if (text_.starts_with("\xEF\xBB\xBF")) pos_ = 3;  // UTF-8 byte order mark of some editors
    Token token = next();
    if (!isKeyword(token.text, "solid")) notStl();
    stl_.openMeshText = "solid\n";
    for (;;) {
      solid(token.line);
      token = next();
      if (token.text.empty()) break;
      if (!isKeyword(token.text, "solid")) {
        fail(token, std::string("only another 'solid' or the end of the file may follow ")
                        .append("'endsolid'; found ")
                        .append(found(token)));
      }
    }
    stl_.openMeshText += "endsolid\n";
    if (stl_.facts.faceCount == 0) fail("no facets (an STL file needs at least one)");
  }

  /// One `solid [name]` … `endsolid [name]` block, its `solid` read (on line `line`).
  void solid(long line) {
    const auto index = static_cast<int32_t>(stl_.solidNames.size());
    stl_.solidNames.emplace_back(wordsOnLine(line, "facet", "endsolid"));
    for (;;) {
      const Token token = next();
      if (token.text.empty()) {
        std::string name =
            stl_.solidNames[index].empty()
                ? std::string("")
                : std::string(" '").append(shownText(stl_.solidNames[index], 80)).append("'");
        fail(Token{{}, line}, std::string("the solid")
                                  .append(name)
                                  .append(" begun here has no 'endsolid': the file ends first"));
      }
      if (isKeyword(token.text, "endsolid")) {
        wordsOnLine(token.line, "solid", "solid");  // its name, if any: not looked at
        return;
      }
      if (!isKeyword(token.text, "facet"))
        fail(token, std::string("expected 'facet normal nx ny nz' or 'endsolid', found ")
                        .append(found(token)));
      facetBody(token.line, index);
    }
  }

  /// The rest of a facet, its `facet` read (on line `line`).
  void facetBody(long line, int32_t solidIndex) {
    expect("normal", "facet normal nx ny nz");
    for (int k = 0; k < 3; ++k) normalValue();
    expect("outer", "outer loop");
    expect("loop", "outer loop");
    std::array<int64_t, 3> corners{};
    stl_.openMeshText += "facet normal 0 0 0\nouter loop\n";
    for (int c = 0; c < 3; ++c) {
      expect("vertex", "vertex x y z");
      std::array<float, 3> value{};
      Vec3 exact;
      stl_.openMeshText += "vertex";
      long cornerLine = 0;
      for (int k = 0; k < 3; ++k) {
        const Token token = next();
        exact[k] = coordinate(token, value[k]);
        cornerLine = token.line;
        // The file's own text, for OpenMesh to read as it would the file.
        stl_.openMeshText.append(" ").append(token.text);
      }
      stl_.openMeshText += "\n";
      corners[c] = cornerVertex(value, exact, cornerLine, stl_.facts.faceCount);
    }
    const Token end = next();
    if (isKeyword(end.text, "vertex"))
      fail(end, "a 4th vertex in a facet's loop: STL facets are triangles (expected 'endloop')");
    if (!isKeyword(end.text, "endloop"))
      fail(end, std::string("expected 'endloop', found ").append(found(end)));
    expect("endfacet", "endfacet");
    stl_.openMeshText += "endloop\nendfacet\n";
    facet(corners, solidIndex, line);
  }

  /// A vertex coordinate: a whole number, finite, within ±1e30 (so also a finite float, which
  /// is what OpenMesh reads); `asFloat` gets the text read as a float, as OpenMesh reads it.
  double coordinate(const Token& token, float& asFloat) {
    if (token.text.empty()) fail(token, "expected 'vertex x y z', found the end of the file");
    double value = 0;
    const NumberStatus status = parseNumber(token.text, value);
    if (status == NumberStatus::kMalformed) {
      fail(token, std::string("'")
                      .append(shownText(token.text, 40))
                      .append("' is not a number (expected 'vertex x y z')"));
    }
    if (status == NumberStatus::kOutOfRange || !std::isfinite(value) ||
        std::abs(value) > kMaxCoordinate) {
      fail(token, std::string("coordinate ")
                      .append(shownText(token.text, 40))
                      .append(" (coordinates must be finite, |x| ≤ 1e30)"));
    }
    std::string_view text = token.text;
    if (text.front() == '+') text.remove_prefix(1);  // parseNumber took it; from_chars does not
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), asFloat);
    if (ec != std::errc() || end != text.data() + text.size()) {
      asFloat = static_cast<float>(value);  // below the smallest float: 0, as OpenMesh reads it
    }
    return value;
  }

  /// A normal's value: only its syntax matters (the winding says which side is lit; some
  /// exporters write nan for the normal of a facet without area).
  void normalValue() {
    const Token token = next();
    double value = 0;
    if (token.text.empty() || parseNumber(token.text, value) == NumberStatus::kMalformed) {
      fail(token, std::string("expected 'facet normal nx ny nz', found ").append(found(token)));
    }
  }

  void expect(const char* keyword, const char* what) {
    const Token token = next();
    if (!isKeyword(token.text, keyword)) {
      fail(token, std::string("expected '").append(what).append("', found ").append(found(token)));
    }
  }

  /// The text of the words that follow on line `line` up to (not including) either keyword;
  /// trimmed, "" if none. Reads them.
  std::string_view wordsOnLine(long line, std::string_view stop1, std::string_view stop2) {
    size_t first = std::string::npos, last = 0;
    for (;;) {
      const size_t pos = pos_;
      const long lineHere = line_, lastLine = lastLine_;
      const Token token = next();
      if (token.text.empty() || token.line != line || isKeyword(token.text, stop1) ||
          isKeyword(token.text, stop2)) {
        pos_ = pos, line_ = lineHere, lastLine_ = lastLine;
        break;
      }
      const auto start = static_cast<size_t>(token.text.data() - text_.data());
      if (first == std::string::npos) first = start;
      last = start + token.text.size();
    }
    if (first == std::string::npos) return {};
    return std::string_view(text_).substr(first, last - first);
  }

  /// The next whitespace-separated word.
  Token next() {
    while (pos_ < text_.size() && isBlank(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !isBlank(text_[pos_])) ++pos_;
    if (pos_ == start) return Token{{}, lastLine_};
    lastLine_ = line_;
    return Token{std::string_view(text_).substr(start, pos_ - start), line_};
  }

  static std::string found(const Token& token) {
    if (token.text.empty()) return "the end of the file";
    return std::string("'").append(shownText(token.text, 40)).append("'");
  }

  // --- both -----------------------------------------------------------------------------------

  /// The vertex of a corner: an earlier one with the same float value (OpenMesh joins them), or
  /// a new one.
  int64_t cornerVertex(const std::array<float, 3>& value, const Vec3& exact, long line,
                       uint64_t f) {
    const CornerKey key{{keyBits(value[0]), keyBits(value[1]), keyBits(value[2])}};
    const auto [it, added] =
        vertexOf_.try_emplace(key, static_cast<int64_t>(stl_.facts.vertices.size()));
    if (added) {
      stl_.facts.vertices.push_back(exact);
      stl_.floatVertices.push_back(value);
    } else if (!(stl_.facts.vertices[it->second] == exact)) {
      if (stl_.joinedCorners == 0) {
        stl_.firstJoinedLine = line;
        stl_.firstJoinedFacet = f;
      }
      ++stl_.joinedCorners;
    }
    return it->second;
  }

  void facet(const std::array<int64_t, 3>& corners, int32_t solidIndex, long line) {
    if (corners[0] == corners[1] || corners[0] == corners[2] || corners[1] == corners[2]) {
      if (stl_.facts.droppedFaces.empty()) stl_.facts.firstDroppedLine = line;
      stl_.facts.droppedFaces.push_back(stl_.facts.faceCount);
    }
    stl_.facets.push_back(corners);
    stl_.facetSolid.push_back(solidIndex);
    ++stl_.facts.faceCount;
  }

  [[noreturn]] void notStl() const {
    std::string binary = std::string("84 + 50 × facets bytes; this file has ")
                             .append(std::to_string(text_.size()))
                             .append(" bytes");
    if (text_.size() < kHeaderBytes) {
      binary += ", fewer than the 84 of its header";
    } else {
      binary.append(" and says ").append(std::to_string(declaredFacets_)).append(" facets");
    }
    fail(std::string("not an STL file: neither binary (")
             .append(binary)
             .append(") nor ASCII (begins with 'solid')"));
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(std::string(path_).append(": ").append(problem));
  }
  /// Fails at the token's line; a file that looks binary is told how binary files are sized.
  [[noreturn]] void fail(const Token& token, const std::string& problem) const {
    std::string hint;
    const bool control = std::any_of(text_.begin(), text_.end(), [](char c) {
      const auto u = static_cast<unsigned char>(c);
      return (u < 0x20 && !isBlank(c)) || u == 0x7f;
    });
    if (control && text_.size() >= kHeaderBytes) {
      hint = std::string(" (the file holds binary bytes: a binary STL, whose header may begin ")
                 .append("with 'solid' too, is exactly 84 + 50 × facets bytes; this one has ")
                 .append(std::to_string(text_.size()))
                 .append(" bytes and says ")
                 .append(std::to_string(declaredFacets_))
                 .append(" facets)");
    }
    throw InputError(path_, token.line, std::string(problem).append(hint));
  }

  const std::string& path_;
  const std::string& text_;
  uint64_t declaredFacets_ = 0;
  size_t pos_ = 0;
  long line_ = 1;
  long lastLine_ = 1;
  StlFile stl_;
  std::unordered_map<CornerKey, int64_t, CornerKeyHash> vertexOf_;
};

}  // namespace

bool sameStlCoordinate(float a, float b) { return keyBits(a) == keyBits(b); }

StlFile checkStlFile(const std::string& path, const std::string& content) {
  return StlWalk(path, content).walk();
}

}  // namespace radiosity::detail
