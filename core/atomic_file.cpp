#include "core/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>

#include "core/error.h"

namespace radiosity {

namespace {

std::string prefixOf(const std::string& path) {
  return std::filesystem::path(path).filename().string() + ".tmp.radiosity-";
}

constexpr const char* kHostCharacters =
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-";

// A temporary's name taken apart: host ("" in the older form), pid; false if it is not one.
bool parseTemporary(const std::filesystem::path& candidate, const std::string& path,
                    std::string& host, long& pid) {
  const std::string name = candidate.filename().string();
  const std::string mark = prefixOf(path);
  if (name.rfind(mark, 0) != 0) return false;
  const std::string rest = name.substr(mark.size());  // [host-]pid-hex
  if (rest.size() < 10 || rest[rest.size() - 9] != '-') return false;
  if (rest.find_first_not_of("0123456789abcdef", rest.size() - 8) != std::string::npos)
    return false;
  const std::string front = rest.substr(0, rest.size() - 9);  // [host-]pid
  const size_t dash = front.rfind('-');
  const std::string digits = dash == std::string::npos ? front : front.substr(dash + 1);
  host = dash == std::string::npos ? "" : front.substr(0, dash);
  if (digits.empty() || digits.size() > 10 ||
      digits.find_first_not_of("0123456789") != std::string::npos)
    return false;
  if (dash != std::string::npos &&
      (host.empty() || host.find_first_not_of(kHostCharacters) != std::string::npos))
    return false;
  pid = std::stol(digits);
  return true;
}

// A process that ended but was not reaped (a killed rank whose parent, mpiexec, is gone, in a
// container whose init reaps nothing) still answers kill(pid, 0): it writes nothing any more.
bool isZombie(long pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(stat, text);
  const size_t end = text.rfind(')');  // the state follows the command name in parentheses
  return end != std::string::npos && end + 2 < text.size() &&
         (text[end + 2] == 'Z' || text[end + 2] == 'X');
}

}  // namespace

std::string hostField() {
  char name[256] = "";
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "host";
  std::string host(name);
  for (char& c : host)
    if (std::strchr(kHostCharacters, c) == nullptr) c = '_';
  if (host.size() <= kHostFieldSize) return host;
  // Too long: its start and a hash of the whole, so that two long names still differ.
  char hash[16];
  std::snprintf(hash, sizeof hash, "%08x",
                static_cast<unsigned>(std::hash<std::string>{}(host)&0xffffffffu));
  return host.substr(0, kHostFieldSize - 9) + "_" + hash;
}

std::string temporaryNameFor(const std::string& path) {
  // A NUL ends the name the system sees: the temporary would be the truncated final name itself
  // ("a" for "a\0b.h5", written straight), and every next name "exists" (a loop for ever).
  if (path.find('\0') != std::string::npos)
    throw Error(exit_code::kUsage,
                path.substr(0, path.find('\0')) + "...: the output's name holds a NUL byte");
  static std::random_device entropy;
  static const std::string host = hostField();
  std::error_code ignored;
  std::string name;
  do {
    char suffix[64];
    std::snprintf(suffix, sizeof suffix, "-%ld-%08x", static_cast<long>(getpid()),
                  static_cast<unsigned>(entropy()));
    name = path + ".tmp.radiosity-" + host + suffix;
  } while (std::filesystem::exists(name, ignored));
  return name;
}

bool isOurTemporary(const std::filesystem::path& candidate, const std::string& path) {
  std::string host;
  long pid = 0;
  return parseTemporary(candidate, path, host, pid);
}

namespace {

// Open MPI's MPI-IO opens a file after a lock test beside it, NAME.locktest.<rank>, removed at
// once; a rank killed in between leaves it, as stale as the temporary it was made for.
std::filesystem::path withoutLockTest(const std::filesystem::path& candidate) {
  const std::string name = candidate.filename().string();
  const std::string mark = ".locktest.";
  const size_t at = name.rfind(mark);
  if (at == std::string::npos || at + mark.size() == name.size() ||
      name.find_first_not_of("0123456789", at + mark.size()) != std::string::npos)
    return candidate;
  return candidate.parent_path() / name.substr(0, at);
}

}  // namespace

bool isStaleTemporary(const std::filesystem::path& candidate, const std::string& path) {
  std::string host;
  long pid = 0;
  if (!parseTemporary(withoutLockTest(candidate), path, host, pid)) return false;
  if (!host.empty() && host != hostField()) return false;  // another machine's: cannot tell
  if (pid <= 0 || pid == static_cast<long>(getpid())) return false;
  if (kill(static_cast<pid_t>(pid), 0) != 0) return errno == ESRCH;
  return isZombie(pid);
}

void removeStaleTemporaries(const std::string& path) {
  const std::filesystem::path target(path);
  const std::filesystem::path directory =
      target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    if (entry.is_regular_file(error) && isStaleTemporary(entry.path(), path))
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
      const std::string why =
          "cannot rename " + file.temporary + " to " + file.path + ": " + error.message();
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
