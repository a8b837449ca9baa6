#include "run/log_file.h"

#include <cerrno>
#include <cstring>
#include <ctime>

#include "core/error.h"

namespace radiosity::run {

void LogFile::write(const std::string& line) {
  if (!file_) {
    held_.push_back(line);
    return;
  }
  std::fprintf(file_.get(), "%s\n", line.c_str());
  std::fflush(file_.get());
}

void LogFile::open(const std::string& path) {
  file_.reset(std::fopen(path.c_str(), "a"));
  if (!file_)
    throw Error(exit_code::kUsage,
                path + ": cannot open the log file for writing: " + std::strerror(errno));
  char started[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(started, sizeof started, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&now));
  write(std::string("radiosity solve, started ") + started);
  for (const std::string& line : held_) write(line);
  held_.clear();
}

}  // namespace radiosity::run
