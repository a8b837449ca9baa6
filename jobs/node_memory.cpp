#include "jobs/node_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <vector>

namespace radiosity::jobs {

namespace {

// Limits from 2^60 bytes up are v1's way of saying "none" (the largest page-aligned int64).
constexpr double kNoLimit = 0x1p60;

// The limit in `file` (a byte count), 0 when it says none or cannot be read.
double readLimit(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string text;
  if (!std::getline(in, text)) return 0;
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  if (text.empty() || text == "max") return 0;
  try {
    size_t used = 0;
    const double bytes = std::stod(text, &used);
    return used == text.size() && bytes > 0 && bytes < kNoLimit ? bytes : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

// The tightest limit in `file` of `leaf` and of every directory above it up to `top`.
double tightestUpTo(std::filesystem::path leaf, const std::filesystem::path& top,
                    const char* file) {
  std::error_code error;
  if (!std::filesystem::is_directory(leaf, error)) leaf = top;  // a cgroup namespace's root
  double tightest = 0;
  for (std::filesystem::path at = leaf;; at = at.parent_path()) {
    const double limit = readLimit(at / file);
    if (limit > 0) tightest = tightest > 0 ? std::min(tightest, limit) : limit;
    if (at == top || !at.has_relative_path() || at == at.parent_path()) break;
  }
  return tightest;
}

}  // namespace

double cgroupMemoryLimit(const std::string& procSelfCgroup,
                         const std::filesystem::path& cgroupRoot) {
  std::istringstream lines(procSelfCgroup);
  std::string line;
  double tightest = 0;
  auto take = [&](double limit) {
    if (limit > 0) tightest = tightest > 0 ? std::min(tightest, limit) : limit;
  };
  while (std::getline(lines, line)) {
    // id:controllers:path (the path may hold ':' itself)
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string id = line.substr(0, first),
                      controllers = line.substr(first + 1, second - first - 1);
    const std::filesystem::path path =
        std::filesystem::path(line.substr(second + 1)).relative_path();
    if (id == "0" && controllers.empty()) {
      take(tightestUpTo(path.empty() ? cgroupRoot : cgroupRoot / path, cgroupRoot, "memory.max"));
      continue;
    }
    std::istringstream names(controllers);
    for (std::string name; std::getline(names, name, ',');)
      if (name == "memory")
        take(tightestUpTo(path.empty() ? cgroupRoot / "memory" : cgroupRoot / "memory" / path,
                          cgroupRoot / "memory", "memory.limit_in_bytes"));
  }
  return tightest;
}

double nodeMemoryBytes() {
  const double physical =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  std::ifstream in("/proc/self/cgroup");
  std::stringstream text;
  text << in.rdbuf();
  const double limit = cgroupMemoryLimit(text.str(), "/sys/fs/cgroup");
  return limit > 0 && (limit < physical || !(physical > 0)) ? limit : physical;
}

}  // namespace radiosity::jobs
