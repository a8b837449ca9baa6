// The one way outputs are written: every writer (result, checkpoint, OBJ+MTL, PNG, study CSV and
// plot, verify CSV) stages its files in an OutputBatch, which gives each a temporary name that
// only this program makes, and renames them into place together once every one is complete.
// After a commit it removes what killed runs left behind under such names — never a user's file
// that merely shares the prefix.
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

/// The outputs of one command. Each is written under the temporary name stage() gives; commit()
/// renames them all only after every one is complete, so a failure anywhere before leaves every
/// existing output as it was. An uncommitted batch removes its temporaries when destroyed.
/// (On a communicator only rank 0 holds one; see io/store/collective_outputs.h.)
class OutputBatch {
 public:
  OutputBatch() = default;
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  /// The temporary name under which to write `path`. `durable`: synced before its rename and
  /// its directory after, so that the rename survives a crash of the machine (checkpoints).
  std::string stage(const std::string& path, bool durable = false);

  /// Renames every staged file into place in the order staged, then removes stale temporaries
  /// of each. Throws Error(exit_code::kFailure) naming the file; the temporaries not yet
  /// renamed are removed then. An empty batch commits nothing.
  void commit();

  /// Removes the temporary of `path` (its write failed) and forgets it; the others stay staged.
  void unstage(const std::string& path);

  /// Removes every temporary; the batch is empty afterwards.
  void discard();

 private:
  struct Staged {
    std::string path, temporary;
    bool durable = false;
  };
  std::vector<Staged> staged_;
};

/// Writes `text` to `temporary`, the staged name of `path`. Throws Error(exit_code::kFailure).
void writeStagedText(const std::string& temporary, const std::string& path,
                     const std::string& text);

/// Writes every (path, text) through one OutputBatch: a second file that cannot be written
/// leaves the first as it was. Throws Error(exit_code::kFailure) naming the file.
void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace radiosity
