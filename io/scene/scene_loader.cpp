// loadScene(): picks the reader by the form of the spec, then validates whatever came back.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"

namespace radiosity {

Mesh loadScene(const std::string& spec) {
  Mesh mesh;
  if (spec.starts_with("builtin:")) {
    mesh = detail::buildBuiltinScene(spec);
  } else {
    std::string extension = std::filesystem::path(spec).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".obj") {
      mesh = detail::readObj(spec);
    } else if (extension == ".ply" || extension == ".off") {
      mesh = detail::readOpenMeshFile(spec);
    } else {
      throw InputError(spec + ": unknown scene format '" + extension +
                       "' (expected .obj, .ply, .off or builtin:NAME)");
    }
  }
  detail::validateScene(mesh, spec);
  return mesh;
}

}  // namespace radiosity
