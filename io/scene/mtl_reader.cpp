#include "io/scene/mtl_reader.h"

#include <cmath>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

std::string joined(const Statement& s) {
  std::string out;
  for (std::string_view token : s.tokens) {
    if (!out.empty()) out += ' ';
    out += token;
  }
  return out;
}

/// "Kd r g b", or "Kd r" meaning grey (as the MTL format allows).
Rgb readColour(const std::string& path, const Statement& s) {
  const std::string_view keyword = s.tokens[0];
  if (s.tokens.size() > 1 && (s.tokens[1] == "spectral" || s.tokens[1] == "xyz")) {
    throw InputError(
        path, s.line,
        std::string(keyword) + " " + std::string(s.tokens[1]) + " is not supported; give r g b");
  }
  if (s.tokens.size() != 2 && s.tokens.size() != 4) {
    throw InputError(path, s.line, std::string(keyword) + " needs three numbers (r g b)");
  }
  Rgb colour;
  for (int c = 0; c < 3; ++c) {
    const std::string_view token = s.tokens[s.tokens.size() == 2 ? 1 : 1 + c];
    const NumberStatus status = parseNumber(token, colour[c]);
    if (status != NumberStatus::kOk) {
      throw InputError(path, s.line,
                       std::string(status == NumberStatus::kMalformed ? "malformed number '"
                                                                      : "number out of range '") +
                           std::string(token) + "' in " + std::string(keyword));
    }
    if (!std::isfinite(colour[c])) {
      throw InputError(path, s.line, "non-finite value in '" + joined(s) + "'");
    }
  }
  return colour;
}

}  // namespace

void readMtl(const std::string& path, std::string content, MaterialLibrary& library) {
  StatementReader reader(path, std::move(content));
  Statement s;
  Material* current = nullptr;
  while (reader.next(s)) {
    const std::string_view keyword = s.tokens[0];
    if (keyword == "newmtl") {
      if (s.rest.empty()) throw InputError(path, s.line, "newmtl without a name");
      current = &library.materials[std::string(s.rest)];
      *current = Material{};
      current->file = path;
      current->line = s.line;
    } else if (keyword == "Kd" || keyword == "Ke") {
      if (current == nullptr) {
        throw InputError(path, s.line, std::string(keyword) + " before any newmtl");
      }
      const Rgb colour = readColour(path, s);
      if (keyword == "Kd") {
        for (double r : colour) {
          if (r < 0 || r > 1) {
            throw InputError(path, s.line,
                             "'" + joined(s) + "': reflectance must be within [0, 1] per channel");
          }
        }
        current->reflectance = colour;
        current->hasKd = true;
      } else {
        for (double e : colour) {
          if (e < 0) throw InputError(path, s.line, "'" + joined(s) + "': negative emission");
          if (e > kMaxEmission)
            throw InputError(path, s.line,
                             "'" + joined(s) +
                                 "': emission above 1e100, beyond what the solver's norms hold "
                                 "(radiosity is linear in E: scale it down, and B up)");
        }
        current->emission = colour;
      }
    } else {
      library.ignoredKeywords.insert(std::string(keyword));
    }
  }
}

}  // namespace radiosity::detail
