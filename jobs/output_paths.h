// Outputs checked before any work: a run that can only fail, or would destroy what it should
// not, is refused at once instead of after the solve.
#pragma once

#include <string>
#include <vector>

namespace radiosity::jobs {

/// Throws Error(exit_code::kUsage) naming the path and the problem when an output's parent
/// directory is missing or not writable; when the output exists and is not a regular file (a
/// device such as /dev/null, a directory, a pipe: the atomic rename would replace it); or when
/// it is the same file as one of `inputs` or as another of `outputs` (compared by device and
/// inode where the file exists, by absolute normal path otherwise). Empty paths are skipped.
void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

}  // namespace radiosity::jobs
