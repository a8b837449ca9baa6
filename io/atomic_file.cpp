#include "io/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "io/io.h"

namespace radiosity {

namespace {

std::string prefixOf(const std::string& path) {
  return std::filesystem::path(path).filename().string() + ".tmp.radiosity-";
}

}  // namespace

std::string temporaryNameFor(const std::string& path) {
  static std::random_device entropy;
  std::error_code ignored;
  std::string name;
  do {
    char suffix[64];
    std::snprintf(suffix, sizeof suffix, ".tmp.radiosity-%ld-%08x", static_cast<long>(getpid()),
                  static_cast<unsigned>(entropy()));
    name = path + suffix;
  } while (std::filesystem::exists(name, ignored));
  return name;
}

bool isOurTemporary(const std::filesystem::path& candidate, const std::string& path) {
  const std::string name = candidate.filename().string();
  const std::string mark = prefixOf(path);
  if (name.rfind(mark, 0) != 0) return false;
  const std::string rest = name.substr(mark.size());
  const size_t dash = rest.find('-');
  if (dash == 0 || dash == std::string::npos || rest.size() - dash - 1 != 8) return false;
  if (rest.find_first_not_of("0123456789") != dash) return false;
  return rest.find_first_not_of("0123456789abcdef", dash + 1) == std::string::npos;
}

void removeStaleTemporaries(const std::string& path) {
  const std::filesystem::path target(path);
  const std::filesystem::path directory =
      target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    if (entry.is_regular_file(error) && isOurTemporary(entry.path(), path))
      std::filesystem::remove(entry.path(), error);
  }
}

void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::string> temporaries;
  auto removeTemporaries = [&] {
    std::error_code ignored;
    for (const std::string& t : temporaries) std::filesystem::remove(t, ignored);
  };
  for (const auto& [path, text] : files) {
    temporaries.push_back(temporaryNameFor(path));
    std::ofstream out(temporaries.back(), std::ios::binary);
    out << text;
    out.close();
    if (!out) {
      removeTemporaries();
      throw Error(exit_code::kFailure, "cannot write " + temporaries.back());
    }
  }
  for (size_t k = 0; k < files.size(); ++k) {
    std::error_code error;
    std::filesystem::rename(temporaries[k], files[k].first, error);
    if (error) {
      removeTemporaries();
      throw Error(exit_code::kFailure,
                  "cannot rename " + temporaries[k] + " to " + files[k].first);
    }
  }
  for (const auto& file : files) removeStaleTemporaries(file.first);
}

}  // namespace radiosity
