#include "run/output_paths.h"

#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"

namespace radiosity::run {

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

// A limit of the file system at `directory` (_PC_NAME_MAX, _PC_PATH_MAX), or `fallback`.
long limitAt(const fs::path& directory, int name, long fallback) {
  const long limit = pathconf(directory.c_str(), name);
  return limit > 0 ? limit : fallback;
}

// The kernel's file systems: writing a result there fails late or does harm.
const char* kernelFileSystem(const fs::path& directory) {
  struct statfs info {};
  if (statfs(directory.c_str(), &info) != 0) return nullptr;
  switch (static_cast<unsigned long>(info.f_type)) {
    case PROC_SUPER_MAGIC:
      return "/proc (procfs)";
    case SYSFS_MAGIC:
      return "/sys (sysfs)";
    case DEBUGFS_MAGIC:
    case TRACEFS_MAGIC:
    case SECURITYFS_MAGIC:
    case CGROUP_SUPER_MAGIC:
    case CGROUP2_SUPER_MAGIC:
    case BPF_FS_MAGIC:
    case PSTOREFS_MAGIC:
    case DEVPTS_SUPER_MAGIC:
    case EFIVARFS_MAGIC:
      return "a kernel file system";
    default:
      break;
  }
  // /dev is a tmpfs like any other by its magic: by its place (its shm/ is for files).
  std::error_code error;
  const std::string real = fs::weakly_canonical(directory, error).string();
  if ((real == "/dev" || real.rfind("/dev/", 0) == 0) && real.rfind("/dev/shm", 0) != 0)
    return "/dev (devices)";
  return nullptr;
}

// The name and its temporary fit the file system (NAME_MAX, PATH_MAX).
void checkLengths(const std::string& path, const fs::path& parent) {
  const size_t name = fs::path(path).filename().string().size() + kLongestTemporarySuffix;
  const long nameMax = limitAt(parent, _PC_NAME_MAX, 255);
  if (name > static_cast<size_t>(nameMax))
    refuse(path, "the name is too long: " + std::to_string(name - kLongestTemporarySuffix) +
                     " bytes, and its temporary adds up to " +
                     std::to_string(kLongestTemporarySuffix) + " to the " +
                     std::to_string(nameMax) + " this file system takes (NAME_MAX)");
  std::error_code error;
  const size_t whole = fs::absolute(path, error).string().size() + kLongestTemporarySuffix;
  const long pathMax = limitAt(parent, _PC_PATH_MAX, 4096);
  if (whole >= static_cast<size_t>(pathMax))
    refuse(path, "the path is too long: with its temporary's name it takes " +
                     std::to_string(whole) + " bytes, above the " + std::to_string(pathMax - 1) +
                     " this system takes (PATH_MAX)");
}

}  // namespace

void checkMpiIoOutputs(const std::vector<std::string>& outputs) {
  for (const std::string& path : outputs) {
    if (path.empty()) continue;
    const size_t whole = path.size() + kLongestTemporarySuffix;
    const size_t name = fs::path(path).filename().string().size() + kLongestTemporarySuffix;
    const long nameMax =
        limitAt(fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path(),
                _PC_NAME_MAX, 255);
    if (whole > kLongestMpiIoPath)
      refuse(path, "the path is too long for MPI-IO: " + std::to_string(path.size()) +
                       " bytes; with its temporary's name (up to " +
                       std::to_string(kLongestTemporarySuffix) + " more) at most " +
                       std::to_string(kLongestMpiIoPath) +
                       " (Open MPI's buffers); use a shorter name or a relative path");
    if (name + kMpiIoNameRoom > static_cast<size_t>(nameMax))
      refuse(path,
             "the name is too long for MPI-IO: " + std::to_string(name - kLongestTemporarySuffix) +
                 " bytes; with its temporary's name and Open MPI's lock files beside it "
                 "at most " +
                 std::to_string(nameMax - kMpiIoNameRoom - kLongestTemporarySuffix));
  }
}

void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const std::string& path = outputs[k];
    if (path.empty()) continue;
    // `-o -` means standard output to a Unix tool; our outputs are files written in place
    // (HDF5, with a temporary renamed over them) or come in pairs (OBJ and its MTL): refused
    // rather than a file named `-`.
    if (path == "-")
      refuse(path,
             "standard output is not an output of radiosity (results are files, written "
             "under a temporary name and renamed): name a file");
    // A NUL ends the name the C library sees: the file written would be another one.
    if (path.find('\0') != std::string::npos)
      refuse(path.substr(0, path.find('\0')) + "...", "the name holds a NUL byte");
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
    if (const char* kernel = kernelFileSystem(parent))
      refuse(path, std::string("cannot write here: the directory is in ") + kernel +
                       ", not a place for files");
    checkLengths(path, parent);
    for (const std::string& input : inputs)
      if (!input.empty() && sameFile(path, input))
        refuse(path, "is also an input (" + input + "): refusing to overwrite it");
    for (size_t other = 0; other < k; ++other)
      if (!outputs[other].empty() && sameFile(path, outputs[other]))
        refuse(path, "is named for two outputs (also " + outputs[other] + ")");
  }
}

}  // namespace radiosity::run
