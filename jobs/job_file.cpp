#include "jobs/job_file.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"

namespace radiosity::jobs {

namespace {

// Where line `line` (from 1) starts in `text`, or its end.
size_t lineStart(std::string_view text, long line) {
  size_t begin = 0;
  for (long at = 1; at < line && begin < text.size(); ++at) {
    const size_t end = text.find('\n', begin);
    begin = end == std::string_view::npos ? text.size() : end + 1;
  }
  return begin;
}

// The text of line `line`, without its end of line.
std::string_view lineOfText(std::string_view text, long line) {
  const std::string_view rest = text.substr(lineStart(text, line));
  return rest.substr(0, rest.find('\n'));
}

// The key a line alone defines (`rays = 2`: rays, `[solve]`: solve, `a.b = 1`: b), or "" when
// the line alone is not TOML.
std::string keyDefinedBy(std::string_view line) {
  try {
    const toml::table table = toml::parse(line);
    const toml::table* at = &table;
    std::string key;
    while (at && at->size() == 1) {
      key = std::string(at->begin()->first.str());
      at = at->begin()->second.as_table();
      if (at && at->is_inline()) break;  // `a = {…}` defines a, not what a holds
    }
    return key;
  } catch (const toml::parse_error&) {
    return "";
  }
}

// The last line before `line` where `key` is defined, at any depth, or 0.
long earlierDefinition(std::string_view text, long line, const std::string& key) {
  const std::string_view before = text.substr(0, lineStart(text, line));
  std::function<long(const toml::table&)> latest = [&](const toml::table& table) {
    long found = 0;
    for (auto&& [name, value] : table) {
      if (name.str() == key) found = std::max<long>(found, name.source().begin.line);
      if (const toml::table* inner = value.as_table()) found = std::max(found, latest(*inner));
    }
    return found;
  };
  try {
    return latest(toml::parse(before));
  } catch (const toml::parse_error&) {
    return 0;
  }
}

// What to do about the usual slips, after toml++'s words for them.
std::string hintFor(const std::string& problem, bool pastEndOfLine) {
  if (problem.find("string: ") != std::string::npos && pastEndOfLine)
    return " (is a closing quote missing?)";
  if (problem.find("could not determine value type") != std::string::npos)
    return " (text goes in quotes: solver = \"gmres\")";
  if (problem.find("not representable in 64 bits") != std::string::npos)
    return " (a larger seed goes in quotes: seed = \"18446744073709551615\")";
  return "";
}

// toml++'s syntax error as "file:line:column: problem". A repeated key (toml++: "cannot
// redefine") reads as any key given twice, naming the first line.
InputError syntaxError(const std::string& path, std::string_view text, const toml::parse_error& e) {
  const long line = e.source().begin.line, column = e.source().begin.column;
  std::string problem(e.description());
  if (problem.find("cannot redefine existing") != std::string::npos) {
    const std::string key = keyDefinedBy(lineOfText(text, line));
    if (const long first = key.empty() ? 0 : earlierDefinition(text, line, key); first > 0) {
      return InputError(
          path, line,
          "'" + shown(key) + "' is given twice (first on line " + std::to_string(first) + ")");
    }
  }
  if (!problem.empty()) problem[0] = static_cast<char>(std::tolower(problem[0]));
  problem += hintFor(problem, column > static_cast<long>(lineOfText(text, line).size()));
  return InputError(path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
                    problem);
}

// The shortest text that reads back as `x` (0.1, not 0.10000000000000001); inf and nan are
// left to the option's own check.
std::string numberText(double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  return std::string(text, end);
}

std::string kindOf(const toml::node& value) {
  if (value.is_array_of_tables()) return "an array of tables";
  if (value.is_array()) return "an array";
  if (value.is_table()) return "a table";
  if (value.is_date()) return "a date";
  if (value.is_time()) return "a time";
  return "a date and time";
}

// One option's value as the text CLI11 parses. Every option of `solve` takes one value, so
// arrays and tables are refused here; a date is no option's value.
std::string optionText(const std::string& path, long line, const std::string& name,
                       const toml::node& value) {
  if (const auto* text = value.as_string()) {
    // TOML lets "\u0000" spell a NUL; the C names it reaches would end there (a result written
    // to "a" for "a\u0000b.h5", past its temporary), so no option takes one.
    if (text->get().find('\0') != std::string::npos)
      throw InputError(
          path, line, "'" + shown(name) + "' holds a NUL character (\\u0000): no option takes one");
    return text->get();
  }
  if (const auto* number = value.as_integer()) return std::to_string(number->get());
  if (const auto* number = value.as_floating_point()) return numberText(number->get());
  if (const auto* flag = value.as_boolean()) return flag->get() ? "true" : "false";
  const bool single = value.is_date() || value.is_time() || value.is_date_time();
  const toml::table* table = value.as_table();
  const std::string where = table && !table->is_inline() && name.find('.') == std::string::npos
                                ? " (a job file holds solve options, at the top or in [solve])"
                                : "";
  throw InputError(path, line,
                   "'" + shown(name) + "' must be " +
                       (single ? "a string, a number or true or false" : "a single value") +
                       ", found " + kindOf(value) + where);
}

struct Entry {
  std::string key, name;  ///< option name, and as written (`solve.rays`) for messages
  toml::source_position where;
  const toml::node* value;
};

// The options at the top and in the [solve] table, in the order of the file.
std::vector<Entry> entriesOf(const toml::table& root) {
  std::vector<Entry> entries;
  for (auto&& [key, value] : root) {
    const std::string name(key.str());
    const toml::table* solve = value.as_table();
    if (name != "solve" || !solve) {
      entries.push_back({name, name, key.source().begin, &value});
      continue;
    }
    for (auto&& [inner, innerValue] : *solve) {
      entries.push_back({std::string(inner.str()), "solve." + std::string(inner.str()),
                         inner.source().begin, &innerValue});
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return std::pair(a.where.line, a.where.column) < std::pair(b.where.line, b.where.column);
  });
  return entries;
}

}  // namespace

std::vector<JobOption> readJobFile(const std::string& path) {
  const std::string text = readSmallFile(path, "job file", kLargestJobFile);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw syntaxError(path, text, e);
  }
  std::vector<JobOption> options;
  std::map<std::string, long> seen;  // TOML allows `rays` at the top and in [solve]: we do not
  for (const Entry& entry : entriesOf(root)) {
    const long line = entry.where.line;
    const auto [earlier, first] = seen.emplace(entry.key, line);
    if (!first) {
      throw InputError(path, line,
                       "'" + shown(entry.key) + "' is given twice (first on line " +
                           std::to_string(earlier->second) + ")");
    }
    options.push_back({entry.key, optionText(path, line, entry.name, *entry.value), line});
  }
  return options;
}

std::string shown(const std::string& text) {
  return text.size() > 60 ? text.substr(0, 60) + "... (" + std::to_string(text.size()) + " bytes)"
                          : text;
}

}  // namespace radiosity::jobs
