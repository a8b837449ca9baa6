// A scan of a PLY header: elements and their properties, nothing of the body.
#include "io/scene/ply_header.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

std::vector<std::string> splitWords(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// The properties OpenMesh 9's PLY reader maps to its own attributes; everything else in the
// vertex and face elements is a "custom" property to it.
bool isOpenMeshStandard(const std::string& element, const PlyProperty& p) {
  static const char* const kVertex[] = {"x",
                                        "y",
                                        "z",
                                        "nx",
                                        "ny",
                                        "nz",
                                        "u",
                                        "s",
                                        "v",
                                        "t",
                                        "red",
                                        "green",
                                        "blue",
                                        "diffuse_red",
                                        "diffuse_green",
                                        "diffuse_blue",
                                        "alpha"};
  if (element == "vertex") {
    return !p.isList &&
           std::find(std::begin(kVertex), std::end(kVertex), p.name) != std::end(kVertex);
  }
  if (p.isList) return p.name == "vertex_indices" || p.name == "vertex_index";
  return p.name == "red" || p.name == "green" || p.name == "blue" || p.name == "alpha";
}

bool isPlyType(const std::string& t) {
  for (const char* known :
       {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
        "int16", "uint16", "int32", "uint32", "float32", "float64"}) {
    if (t == known) return true;
  }
  return false;
}

const PlyProperty* findProperty(const PlyHeader& header, long line) {
  for (const PlyElement& e : header.elements) {
    for (const PlyProperty& p : e.properties) {
      if (p.line == line) return &p;
    }
  }
  return nullptr;
}

}  // namespace

const PlyProperty* PlyHeader::faceProperty(const std::string& name) const {
  for (const PlyElement& e : elements) {
    if (e.name != "face") continue;
    for (const PlyProperty& p : e.properties) {
      if (p.name == name) return &p;
    }
  }
  return nullptr;
}

bool isEightBitPlyType(const std::string& type) {
  return type == "char" || type == "uchar" || type == "int8" || type == "uint8";
}

PlyHeader scanPlyHeader(const std::string& path, const std::string& content) {
  PlyHeader header;
  size_t start = 0;
  bool formatSeen = false;
  for (long line = 1;; ++line) {
    if (start >= content.size()) throw InputError(path, line, "PLY header without end_header");
    size_t end = content.find('\n', start);
    if (end == std::string::npos) end = content.size();
    const std::vector<std::string> w = splitWords(content.substr(start, end - start));
    start = end + 1;
    if (line == 1) {
      if (w.size() != 1 || w[0] != "ply") throw InputError(path, line, "not a PLY file");
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      header.headerEnd = std::min(start, content.size());
      header.headerLines = line;
      break;
    }
    if (w[0] == "format" && w.size() >= 2) {
      header.ascii = w[1] == "ascii";
      header.bigEndian = w[1] == "binary_big_endian";
      formatSeen = true;
    } else if (w[0] == "element" && w.size() >= 2) {
      long long count = 0;
      if (w.size() != 3 || parseInteger(w[2], count) != NumberStatus::kOk || count < 0)
        throw InputError(path, line, "element line needs a name and a non-negative count");
      PlyElement element;
      element.name = w[1];
      element.count = static_cast<uint64_t>(count);
      element.line = line;
      header.elements.push_back(element);
    } else if (w[0] == "property") {
      if (header.elements.empty()) throw InputError(path, line, "property before any element");
      PlyProperty p;
      p.line = line;
      if (w.size() == 5 && w[1] == "list") {
        p.isList = true;
        p.countType = w[2];
        p.typeWord = 3;
        p.type = w[3];
        p.name = w[4];
      } else if (w.size() == 3) {
        p.typeWord = isPlyType(w[1]) || !isPlyType(w[2]) ? 1 : 2;  // OpenMesh takes "NAME TYPE" too
        p.type = w[p.typeWord];
        p.name = w[3 - p.typeWord];
      } else {
        throw InputError(path, line, "malformed property line");
      }
      header.elements.back().properties.push_back(p);
    }
  }
  if (!formatSeen) throw InputError(path + ": PLY header without a format line");
  return header;
}

namespace {

// The custom properties of the vertex and face elements that OpenMesh would read wrongly.
std::vector<long> eightBitCustomLines(const PlyHeader& header) {
  std::vector<long> lines;
  if (!header.ascii) return lines;
  for (const PlyElement& e : header.elements) {
    if (e.name != "vertex" && e.name != "face") continue;
    for (const PlyProperty& p : e.properties) {
      if (!isOpenMeshStandard(e.name, p) && isEightBitPlyType(p.type)) lines.push_back(p.line);
    }
  }
  return lines;
}

}  // namespace

PlyEmission findPlyEmission(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read file");
  std::string text;
  for (std::string line; std::getline(in, line);) {
    text += line + "\n";
    const std::vector<std::string> w = splitWords(line);
    if (!w.empty() && w[0] == "end_header") break;
  }
  const PlyHeader header = scanPlyHeader(path, text);
  PlyEmission emission;
  const PlyProperty* first = nullptr;
  int found = 0;
  for (const std::string& name : emission.names) {
    const PlyProperty* p = header.faceProperty(name);
    if (!p) continue;
    ++found;
    if (!first) first = p;
  }
  if (found == 0) return emission;
  if (found < 3) {
    throw InputError(
        path, first->line,
        "face property '" + first->name + "' needs all of emit_red, emit_green and emit_blue");
  }
  for (int c = 0; c < 3; ++c) {
    const PlyProperty& p = *header.faceProperty(emission.names[c]);
    const bool real =
        p.type == "float" || p.type == "float32" || p.type == "double" || p.type == "float64";
    const bool byte = p.type == "uchar" || p.type == "uint8";
    if (p.isList || !(real || byte)) {
      throw InputError(path, p.line,
                       "face property '" + p.name + "' must be a float, double or uchar, not " +
                           (p.isList ? "a list" : "'" + p.type + "'"));
    }
    emission.scale[c] = byte ? 1.0 / 255 : 1.0;
  }
  emission.present = true;
  emission.needsRetyping = !eightBitCustomLines(header).empty();
  return emission;
}

std::string retypeEightBitCustomProperties(const std::string& path, const std::string& content) {
  const PlyHeader header = scanPlyHeader(path, content);
  const std::vector<long> lines = eightBitCustomLines(header);
  if (lines.empty()) return content;
  std::string out;
  out.reserve(content.size() + 8 * lines.size());
  size_t start = 0;
  for (long line = 1; start < header.headerEnd; ++line) {
    size_t end = content.find('\n', start);
    if (end == std::string::npos) end = content.size();
    if (std::find(lines.begin(), lines.end(), line) == lines.end()) {
      out.append(content, start, end - start);
    } else {  // "property [list COUNT] TYPE NAME" with TYPE now int
      std::vector<std::string> w = splitWords(content.substr(start, end - start));
      const size_t typeWord = findProperty(header, line)->typeWord;
      w[typeWord] = "int";
      for (size_t k = 0; k < w.size(); ++k) out += (k ? " " : "") + w[k];
    }
    out += '\n';
    start = end + 1;
  }
  out.append(content, std::min(header.headerEnd, content.size()), std::string::npos);
  return out;
}

}  // namespace radiosity::detail
