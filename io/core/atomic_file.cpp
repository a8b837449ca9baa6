#include "io/core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "io/core/error.h"

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

namespace {

/// fsync() of a file or directory, best effort: the file is complete either way, this only
/// makes it survive a crash of the machine.
void syncPath(const std::filesystem::path& path, bool directory) {
  const int descriptor = open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (descriptor < 0) return;
  fsync(descriptor);
  close(descriptor);
}

}  // namespace

OutputBatch::~OutputBatch() { discard(); }

std::string OutputBatch::stage(const std::string& path, bool durable) {
  staged_.push_back({path, temporaryNameFor(path), durable});
  return staged_.back().temporary;
}

void OutputBatch::unstage(const std::string& path) {
  std::error_code ignored;
  for (auto file = staged_.begin(); file != staged_.end();) {
    if (file->path != path) {
      ++file;
      continue;
    }
    std::filesystem::remove(file->temporary, ignored);
    file = staged_.erase(file);
  }
}

void OutputBatch::discard() {
  std::error_code ignored;
  for (const Staged& file : staged_) std::filesystem::remove(file.temporary, ignored);
  staged_.clear();
}

void OutputBatch::commit() {
  for (const Staged& file : staged_) {
    // What was written last on disk before the name points to it.
    if (file.durable) syncPath(file.temporary, false);
  }
  for (size_t k = 0; k < staged_.size(); ++k) {
    const Staged& file = staged_[k];
    std::error_code error;
    std::filesystem::rename(file.temporary, file.path, error);
    if (error) {
      const std::string why = "cannot rename " + file.temporary + " to " + file.path + ": " +
                              error.message();
      staged_.erase(staged_.begin(), staged_.begin() + static_cast<std::ptrdiff_t>(k));
      discard();
      throw Error(exit_code::kFailure, why);
    }
    if (file.durable) {
      const std::filesystem::path directory = std::filesystem::path(file.path).parent_path();
      syncPath(directory.empty() ? std::filesystem::path(".") : directory, true);
    }
  }
  for (const Staged& file : staged_) removeStaleTemporaries(file.path);
  staged_.clear();
}

void writeStagedText(const std::string& temporary, const std::string& path,
                     const std::string& text) {
  std::ofstream out(temporary, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw Error(exit_code::kFailure, "cannot write " + path + " (as " + temporary + ")");
}

void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files) {
  OutputBatch batch;
  for (const auto& [path, text] : files) writeStagedText(batch.stage(path), path, text);
  batch.commit();
}

}  // namespace radiosity
