#include "run/node_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <vector>

namespace radiosity::run {

namespace {

// Limits from 2^60 bytes up are v1's way of saying "none" (the largest page-aligned int64).
constexpr double kNoLimit = 0x1p60;

// The tighter of two limits, 0 standing for none.
double tighter(double a, double b) { return a > 0 && b > 0 ? std::min(a, b) : std::max(a, b); }

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

// The tightest limit in `file` of the cgroup at `path` under `top` and of every one above it.
double tightestUpTo(const std::filesystem::path& top, const std::filesystem::path& path,
                    const char* file) {
  std::error_code error;
  std::filesystem::path leaf = path.empty() ? top : top / path;
  if (!std::filesystem::is_directory(leaf, error)) leaf = top;  // a cgroup namespace's root
  double tightest = 0;
  for (std::filesystem::path at = leaf;; at = at.parent_path()) {
    tightest = tighter(tightest, readLimit(at / file));
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
  while (std::getline(lines, line)) {
    // id:controllers:path (the path may hold ':' itself)
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string id = line.substr(0, first),
                      controllers = line.substr(first + 1, second - first - 1);
    const std::filesystem::path path =
        std::filesystem::path(line.substr(second + 1)).relative_path();
    if (id == "0" && controllers.empty()) {
      tightest = tighter(tightest, tightestUpTo(cgroupRoot, path, "memory.max"));
      continue;
    }
    std::istringstream names(controllers);
    for (std::string name; std::getline(names, name, ',');)
      if (name == "memory")
        tightest =
            tighter(tightest, tightestUpTo(cgroupRoot / "memory", path, "memory.limit_in_bytes"));
  }
  return tightest;
}

double nodeMemoryBytes() {
  const double physical =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  std::ifstream in("/proc/self/cgroup");
  std::stringstream text;
  text << in.rdbuf();
  return tighter(physical > 0 ? physical : 0, cgroupMemoryLimit(text.str(), "/sys/fs/cgroup"));
}

}  // namespace radiosity::run
