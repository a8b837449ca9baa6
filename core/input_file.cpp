#include "core/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace radiosity {

std::string notRegularFile(const std::string& path) {
  struct stat status {};
  // stat() follows links and never opens: a FIFO is told without blocking.
  if (stat(path.c_str(), &status) != 0)
    return errno == ENOENT ? "missing" : std::string("unreadable (") + std::strerror(errno) + ")";
  if (S_ISREG(status.st_mode)) return "";
  if (S_ISDIR(status.st_mode)) return "a directory";
  if (S_ISFIFO(status.st_mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(status.st_mode)) return "a socket";
  if (S_ISCHR(status.st_mode) || S_ISBLK(status.st_mode)) return "a device";
  return "not a regular file";
}

void requireRegularFile(const std::string& path, const std::string& kind) {
  // A NUL cuts the name short: the file opened would not be the one named.
  if (path.find('\0') != std::string::npos)
    throw InputError(path.substr(0, path.find('\0')) + "...: the name holds a NUL byte");
  const std::string what = notRegularFile(path);
  if (what.empty()) return;
  if (what == "missing") throw InputError(path + ": cannot read: no such file");
  if (what.rfind("unreadable", 0) == 0) throw InputError(path + ": " + what);
  throw InputError(path + ": is " + what + ", not a " + kind + " (only regular files are read)");
}

std::string readSmallFile(const std::string& path, const std::string& kind, uintmax_t largest) {
  if (const std::string what = notRegularFile(path); !what.empty()) {
    throw InputError(path + ": not a " + kind + " (" +
                     (what == "missing"
                          ? "no such file"
                          : what + ", not a regular file; only regular files are read") +
                     ")");
  }
  std::error_code error;
  const auto bytes = std::filesystem::file_size(path, error);
  if (error || bytes > largest) {
    throw InputError(path + ": not a " + kind + " (" + std::to_string(bytes) + " bytes; a " + kind +
                     " holds at most " + std::to_string(largest) + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + kind);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace radiosity
