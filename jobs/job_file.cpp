#include "jobs/job_file.h"

#include <fstream>

#include "io/io.h"

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
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the job file");
  std::vector<JobOption> options;
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
    text = trim(text);
    if (text.empty() || text == "[solve]") continue;
    size_t equals = text.find('=');
    if (equals == std::string::npos) {
      throw InputError(path, line, "expected 'key = value', found '" + text + "'");
    }
    JobOption option{trim(text.substr(0, equals)), trim(text.substr(equals + 1)), line};
    if (option.key.empty()) throw InputError(path, line, "missing key before '='");
    if (option.value.size() >= 2 && option.value.front() == '"' && option.value.back() == '"') {
      option.value = option.value.substr(1, option.value.size() - 2);
    } else if (option.value.empty()) {
      throw InputError(path, line, "missing value for '" + option.key + "'");
    }
    options.push_back(option);
  }
  return options;
}

}  // namespace radiosity::jobs
