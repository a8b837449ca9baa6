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

/// A fresh temporary name beside `path`: `NAME.tmp.radiosity-<host>-<pid>-<8 hex>`, where
/// <host> is this machine's name (letters, digits, '.', '_' and '-'; at most kHostFieldSize
/// characters) and <pid> this process's id: whose it is, so that a run never takes another
/// live run's temporary for a stale one.
std::string temporaryNameFor(const std::string& path);

/// The longest text temporaryNameFor() adds to a name: for the checks of name lengths.
inline constexpr size_t kHostFieldSize = 16;
inline constexpr size_t kLongestTemporarySuffix =
    sizeof(".tmp.radiosity-") - 1 + kHostFieldSize + 1 + 7 + 1 + 8;  // pids have ≤ 7 digits

/// This machine's name as temporaries carry it (see temporaryNameFor).
std::string hostField();

/// Whether `candidate` is such a temporary of `path` (by its name alone: a write killed early
/// leaves a file without any content to recognise): the form above, or the older
/// `NAME.tmp.radiosity-<pid>-<8 hex>` (taken to be of this machine).
bool isOurTemporary(const std::filesystem::path& candidate, const std::string& path);

/// Whether the temporary `candidate` of `path` was left by a run that is gone: one of this
/// machine whose process no longer exists (kill(pid, 0) fails with ESRCH, or it is a zombie).
/// Another machine's (a shared file system) or a live process's is not: it may be writing now.
/// So is the lock test Open MPI's MPI-IO makes beside a temporary it opens
/// (`TEMPORARY.locktest.<rank>`), which a rank killed while opening it leaves.
bool isStaleTemporary(const std::filesystem::path& candidate, const std::string& path);

/// Removes the temporaries of `path` that runs which are gone left; call it once a write of
/// `path` succeeded. Errors are ignored (a stale file is harmless).
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
