// The one way outputs are named while they are written: every writer (result, checkpoint,
// OBJ+MTL, PNG, study CSV and plot) writes under a temporary name that only this program gives,
// renames it into place when complete, and, after a write succeeded, removes what killed runs
// left behind under such names — never a user's file that merely shares the prefix.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

/// A fresh temporary name beside `path`: `NAME.tmp.radiosity-<pid>-<8 hex>`.
std::string temporaryNameFor(const std::string& path);

/// Whether `candidate` is such a temporary of `path` (by its name alone: a write killed early
/// leaves a file without any content to recognise).
bool isOurTemporary(const std::filesystem::path& candidate, const std::string& path);

/// Removes the temporaries of `path` that killed runs left; call it once a write of `path`
/// succeeded. Errors are ignored (a stale file is harmless).
void removeStaleTemporaries(const std::string& path);

/// Writes every (path, text) under a temporary name and renames them only when all are
/// complete: a second file that cannot be written leaves the first as it was. Throws
/// Error(exit_code::kFailure) naming the file; no temporary is left then.
void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace radiosity
