// --log-file: the log also written to a file, as batch jobs keep it beside the scheduler's own.
// Lines are held until the run has checked that the file is none of its inputs or outputs
// (open()), so a refused run leaves no file; then the file is appended to (a requeued job's runs
// follow each other) and flushed line by line, for `tail -f`. Rank 0's console writes it.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace radiosity::run {

class LogFile {
 public:
  /// Appends `line`, or holds it until open().
  void write(const std::string& line);
  /// Opens `path` for appending, writes a line naming the run's start and the lines held.
  /// Throws Error(exit_code::kUsage) naming the path when it cannot be opened.
  void open(const std::string& path);
  bool isOpen() const { return file_ != nullptr; }

 private:
  struct Closer {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  std::unique_ptr<std::FILE, Closer> file_;
  std::vector<std::string> held_;
};

}  // namespace radiosity::run
