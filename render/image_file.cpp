#include "render/image_file.h"

#include <cerrno>
#include <cstring>

#include "core/atomic_file.h"
#include "core/error.h"

namespace radiosity::render {

void writeImageFile(const std::string& path, const std::function<std::string(std::FILE*)>& encode) {
  auto fail = [&](const std::string& why) {
    return Error(exit_code::kFailure, "cannot write the picture '" + path + "': " + why);
  };
  OutputBatch batch;
  std::FILE* file = std::fopen(batch.stage(path).c_str(), "wbx");  // x: never an existing file
  if (!file) throw fail(std::strerror(errno));
  std::string why = encode(file);
  if (std::fflush(file) != 0 && why.empty()) why = std::strerror(errno);
  if (std::fclose(file) != 0 && why.empty()) why = std::strerror(errno);
  if (!why.empty()) throw fail(why);
  batch.commit();
}

}  // namespace radiosity::render
