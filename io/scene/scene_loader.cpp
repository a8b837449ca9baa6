// loadScene(): picks the reader by the form of the spec, then validates whatever came back.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/error.h"
#include "core/input_file.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"

namespace radiosity {

namespace {

std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

bool isHdf5Scene(const std::string& spec) {
  if (spec.starts_with("builtin:")) return false;
  const std::string extension = lowerExtension(spec);
  return extension == ".h5" || extension == ".hdf5";
}

Mesh loadScene(const std::string& spec) {
  Mesh mesh;
  if (spec.starts_with("builtin:")) {
    mesh = detail::buildBuiltinScene(spec);
  } else if (isHdf5Scene(spec)) {
    // Parallel HDF5 needs the communicator (and this library has neither MPI nor HDF5).
    throw Error(exit_code::kFailure,
                spec +
                    ": internal error: an HDF5 scene is read by all ranks together, through "
                    "loadScene(spec, comm) of io/store/scene_file.h");
  } else {
    requireRegularFile(spec, "scene file");
    const std::string extension = lowerExtension(spec);
    if (extension == ".obj") {
      mesh = detail::readObj(spec);
    } else if (extension == ".ply" || extension == ".off") {
      mesh = detail::readOpenMeshFile(spec);
    } else if (extension == ".stl") {
      mesh = detail::readStl(spec);
    } else if (extension == ".vs3") {
      mesh = detail::readVs3(spec);
    } else {
      throw InputError(spec + ": unknown scene format '" + extension +
                       "' (expected .obj, .ply, .off, .stl, .vs3, .h5 or builtin:NAME)");
    }
  }
  if (!spec.starts_with("builtin:")) mesh.sourceFiles.insert(mesh.sourceFiles.begin(), spec);
  validateScene(mesh, spec);
  return mesh;
}

}  // namespace radiosity
