#include "jobs/job_file_expansion.h"

#include <cctype>

#include "jobs/job_file.h"

namespace radiosity::jobs {

namespace {

// The job file `--config FILE` or `--config=FILE` names (empty: none), and the other arguments.
std::pair<std::string, std::vector<std::string>> takeJobFile(
    const std::vector<std::string>& arguments) {
  std::vector<std::string> rest;
  std::string jobFile;
  for (size_t i = 0; i < arguments.size(); ++i) {
    std::string named;
    if (arguments[i] == "--config" && i + 1 < arguments.size()) {
      named = arguments[++i];
    } else if (arguments[i].rfind("--config=", 0) == 0) {
      named = arguments[i].substr(9);
    } else {
      rest.push_back(arguments[i]);
      continue;
    }
    // One job file: a second would silently replace the first (they are not layered).
    if (!jobFile.empty())
      throw Error(exit_code::kUsage, "--config is given twice (" + shown(jobFile) + " and " +
                                         shown(named) + "): give one job file");
    jobFile = named;
  }
  return {jobFile, rest};
}

// Whether `word` stands in `message` on its own, not as part of a longer name or number.
bool hasWord(const std::string& message, const std::string& word) {
  auto inWord = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
  };
  for (size_t at = message.find(word); at != std::string::npos; at = message.find(word, at + 1)) {
    const size_t after = at + word.size();
    if ((at == 0 || !inWord(message[at - 1]) || word.front() == '-') &&
        (after == message.size() || !inWord(message[after])))
      return true;
  }
  return false;
}

}  // namespace

ExpandedArguments expandJobFile(const std::vector<std::string>& arguments,
                                const CLI::App& command) {
  ExpandedArguments expanded;
  for (size_t i = 1; i < arguments.size(); ++i)
    expanded.origin.alsoOnCommandLine.insert(arguments[i].substr(0, arguments[i].find('=')));
  const auto [jobFile, rest] = takeJobFile(arguments);
  if (jobFile.empty() || rest.empty() || rest[0] != command.get_name()) {
    expanded.arguments = arguments;
    return expanded;
  }
  expanded.arguments.push_back(rest[0]);
  expanded.origin.file = jobFile;
  for (const JobOption& option : readJobFile(jobFile)) {
    const CLI::Option* known = command.get_option_no_throw("--" + option.key);
    if (!known || option.key == "config" || option.key == "help") {
      throw InputError(jobFile, option.line, "unknown key '" + shown(option.key) + "'");
    }
    expanded.origin.lineOfKey["--" + option.key] = {option.line, option.value};
    if (known->get_expected_min() == 0) {  // a flag: true or false
      if (option.value == "true") {
        expanded.arguments.push_back("--" + option.key);
      } else if (option.value != "false") {
        throw InputError(
            jobFile, option.line,
            "'" + option.key + "' takes true or false, not '" + shown(option.value) + "'");
      }
      continue;
    }
    expanded.arguments.push_back("--" + option.key);
    expanded.arguments.push_back(option.value);
  }
  expanded.arguments.insert(expanded.arguments.end(), rest.begin() + 1, rest.end());
  return expanded;
}

void throwParseRefusal(const std::string& message, const JobFileOrigin& origin) {
  for (const auto& [option, where] : origin.lineOfKey) {
    const auto& [line, value] = where;
    const bool ours = origin.alsoOnCommandLine.count(option) == 0 || hasWord(message, value);
    if (hasWord(message, option) && ours) throw InputError(origin.file, line, message);
  }
  throw Error(exit_code::kUsage, message + " (run with --help for usage)");
}

}  // namespace radiosity::jobs
