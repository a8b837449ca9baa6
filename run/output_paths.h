// Outputs checked before any work: a run that can only fail, or would destroy what it should
// not, is refused at once instead of after the solve.
#pragma once

#include <string>
#include <vector>

namespace radiosity::run {

/// Throws Error(exit_code::kUsage) naming the path and the problem when an output's parent
/// directory is missing or not writable; when the output exists and is not a regular file (a
/// device such as /dev/null, a directory, a pipe: the atomic rename would replace it); or when
/// it is the same file as one of `inputs` or as another of `outputs` (compared by device and
/// inode where the file exists, by absolute normal path otherwise). Also when its name or its
/// temporary's (core/atomic_file.h) is longer than the file system takes (NAME_MAX, PATH_MAX
/// by pathconf), when it holds a NUL byte, or when its directory is on a kernel file system
/// (/proc, /sys, /dev...) where no result belongs, and when it is `-` (standard output, which no
/// output of ours is). Empty paths are skipped.
void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

/// The longest name, as given, of a file written through MPI-IO (HDF5 outputs), and the room its
/// last component must leave below NAME_MAX. Open MPI 4.1's OMPIO writes "NAME.locktest" into a
/// 256-byte buffer (sharedfp/lockedfile: `buffer overflow detected`, an abort, from 247 bytes)
/// and creates "NAME-<job id>-<pid>.lock" beside the file (MPI_File_open fails, or one rank
/// hangs, when that is longer than NAME_MAX); both are for the temporary name actually opened.
inline constexpr size_t kLongestMpiIoPath = 240;
inline constexpr size_t kMpiIoNameRoom = 24;

/// checkOutputs' refusals for files written through MPI-IO: Error(exit_code::kUsage) when the
/// temporary of any of `outputs` would pass the limits above.
void checkMpiIoOutputs(const std::vector<std::string>& outputs);

}  // namespace radiosity::run
