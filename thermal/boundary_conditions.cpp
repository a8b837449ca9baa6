// Reading a thermal boundary-condition file (TOML) into BoundaryConditions, every problem named
// by file and line.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string_view>

#include "core/error.h"
#include "core/input_file.h"
#include "core/shown_text.h"
#include "thermal/thermal.h"

namespace radiosity::thermal {

namespace {

// A boundary-condition file is small: a table per surface.
constexpr uintmax_t kLargestFile = 1 << 20;

constexpr const char* kKeys = "emissivity, and temperature or heat_flux";

// The shortest text that reads back as x: 1.0000001 is not "1" (six digits) in a refusal.
std::string numberText(double x) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, x).ptr);
}

// The table header `[...]` (or `[[...]]`) that starts line `line` (1-based) of `text`, as
// written, quotes and all; empty if that line holds none.
std::string headerAt(std::string_view text, long line) {
  size_t at = 0;
  for (long l = 1; l < line && at != std::string_view::npos; ++l) {
    at = text.find('\n', at);
    if (at != std::string_view::npos) ++at;
  }
  if (at == std::string_view::npos) return "";
  const std::string_view rest = text.substr(at, text.find('\n', at) - at);
  const size_t start = rest.find_first_not_of(" \t");
  if (start == std::string_view::npos || rest[start] != '[') return "";
  char quote = 0;
  for (size_t k = start; k < rest.size(); ++k) {
    const char c = rest[k];
    if (quote != 0) {
      if (c == '\\' && quote == '"')
        ++k;
      else if (c == quote)
        quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == ']') {
      const size_t end = k + 1 < rest.size() && rest[k + 1] == ']' ? k + 2 : k + 1;
      return std::string(rest.substr(start, end - start));
    }
  }
  return "";
}

// toml++ names a table defined twice by a garbled key ('surface."roroof"' for
// [surface."roof"]): the message names it as the file writes it, and where it was first.
std::string redefinedTable(std::string_view text, long line) {
  const std::string header = headerAt(text, line);
  if (header.empty()) return "";
  for (long l = 1; l < line; ++l)
    if (headerAt(text, l) == header)
      return "table " + shownText(header, 80) + " is defined twice (first at line " +
             std::to_string(l) + "): give each table once";
  return "table " + shownText(header, 80) + " is defined twice: give each table once";
}

long lineOf(const toml::node& node) { return static_cast<long>(node.source().begin.line); }

// The number at `key` of `table`, finite; the key's line for messages.
double numberAt(const toml::table& table, const std::string& key, const std::string& path) {
  const toml::node& node = *table.get(key);
  const std::optional<double> value = node.value<double>();  // integers convert too
  if (!value || node.is_boolean()) throw InputError(path, lineOf(node), key + " must be a number");
  if (!std::isfinite(*value))
    throw InputError(path, lineOf(node), key + " must be finite, not " + numberText(*value));
  return *value;
}

SurfaceCondition readCondition(const toml::table& table, const std::string& name, long line,
                               const std::string& path) {
  const std::string what = name.empty() ? "[default]" : "[surface.\"" + shownText(name, 80) + "\"]";
  SurfaceCondition c;
  c.name = name;
  c.line = line;
  for (const auto& [key, node] : table) {
    const std::string k(key.str());
    if (k != "emissivity" && k != "temperature" && k != "heat_flux")
      throw InputError(
          path, lineOf(node),
          what + ": unknown key '" + shownText(k, 60) + "' (a surface takes " + kKeys + ")");
  }
  c.emissivityGiven = table.contains("emissivity");
  if (c.emissivityGiven) c.emissivity = numberAt(table, "emissivity", path);
  if (c.emissivityGiven) {
    const std::string problem = emissivityProblem(c.emissivity);
    if (!problem.empty())
      throw InputError(path, lineOf(*table.get("emissivity")), what + ": " + problem);
  }
  const bool hasT = table.contains("temperature"), hasQ = table.contains("heat_flux");
  if (hasT == hasQ)
    throw InputError(path, line,
                     what + (hasT ? ": both temperature and heat_flux; give exactly one"
                                  : ": neither temperature (K) nor heat_flux (W/m^2); give one"));
  if (hasT) {
    const double t = numberAt(table, "temperature", path);
    const long at = lineOf(*table.get("temperature"));
    if (t < 0)
      throw InputError(path, at,
                       what + ": temperature " + numberText(t) + " K is below absolute zero");
    if (!(c.emissivity * kStefanBoltzmann * std::pow(t, 4) <= kMaxEmission))
      throw InputError(path, at,
                       what + ": temperature " + numberText(t) +
                           " K emits more than the solver takes (" + "εσT^4 above 1e100 W/m^2)");
    c.temperature = t;
  } else {
    const double q = numberAt(table, "heat_flux", path);
    if (std::abs(q) > kMaxEmission)
      throw InputError(path, lineOf(*table.get("heat_flux")),
                       what + ": heat_flux beyond 1e100 W/m^2 in size");
    c.heatFlux = q;
  }
  return c;
}

// [surroundings]: the temperature of the black surroundings that what leaves the scene goes to.
void readSurroundings(const toml::node& node, const std::string& path,
                      BoundaryConditions& conditions) {
  if (!node.is_table())
    throw InputError(path, lineOf(node),
                     "surroundings must be a table: [surroundings] with temperature (K)");
  const toml::table& table = *node.as_table();
  for (const auto& [key, value] : table)
    if (key.str() != "temperature")
      throw InputError(path, lineOf(value),
                       "[surroundings]: unknown key '" + shownText(std::string(key.str()), 60) +
                           "' (the surroundings take temperature (K): they are black)");
  if (!table.contains("temperature"))
    throw InputError(path, lineOf(node), "[surroundings]: no temperature (K); give one");
  const double t = numberAt(table, "temperature", path);
  const long at = lineOf(*table.get("temperature"));
  if (t < 0)
    throw InputError(path, at,
                     "[surroundings]: temperature " + numberText(t) + " K is below absolute zero");
  if (!(kStefanBoltzmann * std::pow(t, 4) <= kMaxEmission))
    throw InputError(path, at,
                     "[surroundings]: temperature " + numberText(t) +
                         " K emits more than the solver takes (sigma T^4 above 1e100 W/m^2)");
  conditions.surroundingsTemperature = t;
  conditions.surroundingsLine = at;
}

}  // namespace

std::string emissivityProblem(double emissivity) {
  if (emissivity > 1)
    return "emissivity " + numberText(emissivity) +
           " is above 1 (no grey surface emits more than a black one)";
  if (!(emissivity >= kLeastEmissivity))
    return "emissivity " + numberText(emissivity) + " is below " + numberText(kLeastEmissivity) +
           ", the least a thermal run takes (such a surface reflects 1 - emissivity of what "
           "reaches it, which the solver cannot tell from 1: its temperature would be lost)";
  return "";
}

BoundaryConditions parseBoundaryConditions(const std::string& text, const std::string& path) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    std::string problem(e.description());
    if (!problem.empty()) problem[0] = static_cast<char>(std::tolower(problem[0]));
    const long line = static_cast<long>(e.source().begin.line);
    if (problem.find("cannot redefine existing table") != std::string::npos) {
      const std::string redefined = redefinedTable(text, line);
      if (!redefined.empty()) throw InputError(path, line, redefined);
    }
    throw InputError(path + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": " + problem);
  }
  BoundaryConditions conditions;
  conditions.path = path;
  for (const auto& [key, node] : root) {
    const std::string k(key.str());
    if (k == "default") {
      if (!node.is_table())
        throw InputError(path, lineOf(node), "default must be a table: [default]");
      conditions.fallback = readCondition(*node.as_table(), "", lineOf(node), path);
    } else if (k == "surface") {
      if (!node.is_table())
        throw InputError(path, lineOf(node),
                         "surface must hold tables: [surface.\"NAME\"], one per surface");
      for (const auto& [name, inner] : *node.as_table()) {
        if (!inner.is_table())
          throw InputError(path, lineOf(inner),
                           "surface." + shownText(std::string(name.str()), 60) +
                               " must be a table: [surface.\"NAME\"] with " + kKeys);
        if (name.str().empty())
          throw InputError(path, lineOf(inner), "[surface.\"\"]: a surface needs a name");
        conditions.surfaces.push_back(
            readCondition(*inner.as_table(), std::string(name.str()), lineOf(inner), path));
      }
    } else if (k == "surroundings") {
      readSurroundings(node, path, conditions);
    } else {
      throw InputError(path, lineOf(node),
                       "unknown key '" + shownText(k, 60) +
                           "' (a thermal file holds [surface.\"NAME\"] tables, a [default] "
                           "table and a [surroundings] table)");
    }
  }
  // (toml++ keeps a table's keys sorted: back to the file's order)
  std::stable_sort(
      conditions.surfaces.begin(), conditions.surfaces.end(),
      [](const SurfaceCondition& a, const SurfaceCondition& b) { return a.line < b.line; });
  if (conditions.surfaces.empty() && !conditions.fallback)
    throw InputError(path + ": no [surface.\"NAME\"] table and no [default]: nothing to solve");
  return conditions;
}

BoundaryConditions readBoundaryConditions(const std::string& path) {
  return parseBoundaryConditions(
      readSmallFile(path, "thermal boundary-condition file", kLargestFile), path);
}

}  // namespace radiosity::thermal
