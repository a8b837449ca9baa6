// Private to io/store: the checkpoint reader's checked parts on one process, for `radiosity
// info`'s description of a checkpoint (checkpoint_description.cpp), which reads what the
// reader reads and refuses what it refuses.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/store/checkpoint.h"
#include "io/store/hdf5_util.h"

namespace radiosity {

/// Opens `path` and checks that it is a checkpoint. InputError otherwise.
h5::Handle openCheckpoint(const std::string& path);

/// What a checkpoint holds besides the rows: attributes, identity, history, refinement. `rows`
/// is left empty. InputError for a file this program cannot read or a corrupted one.
Checkpoint readCheckpointShared(hid_t file, const std::string& path);

/// The samples of each of the checkpoint's `rows` rows, checked (from 0 to 2^32 - 1).
/// InputError for a corrupted dataset.
std::vector<int64_t> readCheckpointSamples(hid_t file, const std::string& path, int64_t rows);

}  // namespace radiosity
