// Job files (--config FILE): one option per line, `key = value`, keys being the long option
// names without dashes (`rays = 4096`, `solver = "gmres"`, `quiet = true`); `#` starts a
// comment; a `[solve]` section header is allowed. Options given on the command line win.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace radiosity::jobs {

struct JobOption {
  std::string key;
  std::string value;
  long line = 0;
};

/// Reads the job file; throws InputError("file:line: problem") on a malformed line or a
/// missing file.
std::vector<JobOption> readJobFile(const std::string& path);

}  // namespace radiosity::jobs
