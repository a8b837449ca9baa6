#include "jobs/job_file.h"

#include <filesystem>
#include <fstream>
#include <map>

#include "io/core/error.h"

namespace radiosity::jobs {

namespace {

std::string trim(const std::string& text) {
  const char* space = " \t\r\n";
  size_t first = text.find_first_not_of(space);
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(space) - first + 1);
}

}  // namespace

std::vector<JobOption> readJobFile(const std::string& path) {
  // A job file is a small regular file: a directory, a device (/dev/zero never ends) or a
  // huge file is refused before reading.
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw InputError(
        path + ": not a job file (" +
        (std::filesystem::exists(path, error) ? "not a regular file" : "no such file") + ")");
  }
  const auto bytes = std::filesystem::file_size(path, error);
  if (error || bytes > kLargestJobFile) {
    throw InputError(path + ": not a job file (" + std::to_string(bytes) +
                     " bytes; a job file holds at most " + std::to_string(kLargestJobFile) + ")");
  }
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the job file");
  std::vector<JobOption> options;
  std::map<std::string, long> seen;
  std::string text;
  for (long line = 1; std::getline(in, text); ++line) {
    // A '#' inside a quoted value is part of the value.
    bool quoted = false;
    for (size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '"') quoted = !quoted;
      if (text[i] == '#' && !quoted) {
        text.resize(i);
        break;
      }
    }
    if (quoted) throw InputError(path, line, "unterminated quote");
    text = trim(text);
    if (text.empty() || text == "[solve]") continue;
    size_t equals = text.find('=');
    if (equals == std::string::npos) {
      throw InputError(path, line, "expected 'key = value', found '" + shown(text) + "'");
    }
    JobOption option{trim(text.substr(0, equals)), trim(text.substr(equals + 1)), line};
    if (option.key.empty()) throw InputError(path, line, "missing key before '='");
    if (option.value.size() >= 2 && option.value.front() == '"' && option.value.back() == '"') {
      option.value = option.value.substr(1, option.value.size() - 2);
    } else if (option.value.empty()) {
      throw InputError(path, line, "missing value for '" + shown(option.key) + "'");
    }
    const auto [earlier, first] = seen.emplace(option.key, line);
    if (!first) {
      throw InputError(path, line,
                       "'" + shown(option.key) + "' is given twice (first on line " +
                           std::to_string(earlier->second) + ")");
    }
    options.push_back(option);
  }
  return options;
}

std::string shown(const std::string& text) {
  return text.size() > 60 ? text.substr(0, 60) + "... (" + std::to_string(text.size()) + " bytes)"
                          : text;
}

}  // namespace radiosity::jobs
