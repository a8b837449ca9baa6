// Job files (--config FILE) are TOML, parsed by toml++ (Debian's libtomlplusplus-dev), so any
// TOML spelling of a value works ('single quotes', 4_096, 0xff, 1e-3, multi-line strings). Keys
// are the long option names without dashes (`rays = 4096`, `solver = "gmres"`, `quiet = true`),
// at the top or in a `[solve]` table; options given on the command line win.
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

/// Reads the job file: each option with its value as the text CLI11 parses (integers in decimal,
/// floats in the shortest text that reads back the same, true/false) and its line. Throws
/// InputError("file:line:column: problem") on a TOML syntax error, InputError("file:line:
/// problem") on a key given twice or a value that is not one string, number or true/false (an
/// array, a table other than [solve], a date), and InputError("file: problem") on a missing,
/// non-regular or oversized file.
std::vector<JobOption> readJobFile(const std::string& path);

/// `text` as an error message shows it: at most 60 characters and the length.
std::string shown(const std::string& text);

}  // namespace radiosity::jobs
