// The one way render/ writes a picture file: under a temporary name beside it, every step of the
// write checked (a full disk may only show when the buffers are flushed), renamed into place when
// complete. Private to render/.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

namespace radiosity::render {

/// Writes `path` by `encode`, which writes the picture to the open file and returns "" or why it
/// failed. On failure nothing is left, an existing `path` is unchanged, and Error(kFailure) names
/// the file and the cause. Serial.
void writeImageFile(const std::string& path, const std::function<std::string(std::FILE*)>& encode);

}  // namespace radiosity::render
