#include "jobs/output_paths.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "io/core/error.h"

namespace radiosity::jobs {

namespace {

namespace fs = std::filesystem;

// The same file: the same device and inode if both exist, else the same absolute path.
bool sameFile(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  if (stat(a.c_str(), &sa) == 0 && stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code error;
  return fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
}

[[noreturn]] void refuse(const std::string& path, const std::string& problem) {
  throw Error(exit_code::kUsage, path + ": " + problem);
}

}  // namespace

void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const std::string& path = outputs[k];
    if (path.empty()) continue;
    fs::path parent = fs::path(path).parent_path();
    if (parent.empty()) parent = ".";
    std::error_code error;
    if (!fs::is_directory(parent, error))
      refuse(path, "cannot write here: no directory " + parent.string());
    if (access(parent.c_str(), W_OK | X_OK) != 0)
      refuse(path, "cannot write here: the directory " + parent.string() + " is not writable");
    struct stat status {};
    if (lstat(path.c_str(), &status) == 0 && !S_ISREG(status.st_mode))
      refuse(path,
             "is not a regular file (a device, directory, pipe or link): refusing to "
             "replace it with the output");
    for (const std::string& input : inputs)
      if (!input.empty() && sameFile(path, input))
        refuse(path, "is also an input (" + input + "): refusing to overwrite it");
    for (size_t other = 0; other < k; ++other)
      if (!outputs[other].empty() && sameFile(path, outputs[other]))
        refuse(path, "is named for two outputs (also " + outputs[other] + ")");
  }
}

}  // namespace radiosity::jobs
