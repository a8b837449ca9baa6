// Job files (--config FILE): one option per line, `key = value`, keys being the long option
// names without dashes (`rays = 4096`, `solver = "gmres"`, `quiet = true`); `#` starts a
// comment; a `[solve]` section header is allowed. Options given on the command line win.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace radiosity::jobs {

struct JobOption {
  std::string key;
  std::string value;
  long line = 0;
};

/// The largest job file read: a job file is a few lines.
inline constexpr uintmax_t kLargestJobFile = 1 << 20;

/// Reads the job file; throws InputError("file:line: problem") on a malformed line, an
/// unterminated quote or a key given twice, and InputError("file: problem") on a missing,
/// non-regular or oversized file.
std::vector<JobOption> readJobFile(const std::string& path);

/// `text` as an error message shows it: at most 60 characters and the length.
std::string shown(const std::string& text);

}  // namespace radiosity::jobs
