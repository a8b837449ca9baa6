// The one check before any input file is opened: only a regular file is read. Opening a FIFO
// blocks until someone writes to it (a run that hangs), a device may never end, and a directory
// is no file; all are refused by name instead (exit 3).
#pragma once

#include <cstdint>
#include <string>

namespace radiosity {

/// Throws InputError("PATH: ...") unless `path` (after symbolic links) is an existing regular
/// file: "cannot read: no such file", "is a directory, not a KIND", "is a FIFO (named pipe), not a
/// KIND", "is a device, not a KIND". `kind` ("result file", "job file") is what the caller
/// expected. Never opens the file, so it cannot block.
void requireRegularFile(const std::string& path, const std::string& kind);

/// What `path` is when it is not a regular file ("a directory", "a FIFO (named pipe)", "a
/// device", "a socket", "missing"), "" when it is one. Never throws, never opens it.
std::string notRegularFile(const std::string& path);

/// The whole of a small text input (a job file, a thermal boundary-condition file): only a
/// regular file of at most `largest` bytes is read, so that a directory, a FIFO (which would
/// block), a device (which never ends) or a huge file is refused by name before any read.
/// InputError "PATH: not a KIND (...)" or "PATH: cannot open the KIND".
std::string readSmallFile(const std::string& path, const std::string& kind, uintmax_t largest);

}  // namespace radiosity
