// Scenes in HDF5 (docs/scene-format.md): the result file's /mesh with a material table, labels and
// source faces, so that a large scene is read fast by every rank together instead of parsed from
// text by each. `radiosity scene FILE -o FILE.h5` writes one.
#pragma once

#include <mpi.h>

#include <map>
#include <string>

#include "core/mesh.h"

namespace radiosity {

/// loadScene(spec) (io/scene/scene.h) for every rank of `comm`, an HDF5 scene file (.h5, .hdf5)
/// included: that one is read with parallel HDF5 by all ranks together. Every rank gets the same
/// mesh, validated as loadScene() validates it, or throws the same InputError (naming the file,
/// the dataset and the problem). Collective.
Mesh loadScene(const std::string& spec, MPI_Comm comm);

/// Reads the HDF5 scene file `path` on every rank of `comm` (what loadScene(spec, comm) does for
/// one). Collective.
Mesh readSceneFile(MPI_Comm comm, const std::string& path);

/// Whether `path` is an HDF5 file with the root attribute kind = "radiosity scene". Never throws.
bool isSceneFile(const std::string& path);

/// What `radiosity info` prints for a scene file: counts, length unit, extent, the materials,
/// what made it. The scene is read and checked whole on the calling rank (InputError as from
/// readSceneFile). MPI must be initialised.
std::string describeSceneFile(const std::string& path);

/// What a scene file records besides the mesh.
struct SceneFileAttributes {
  std::string source;  ///< the scene it was made from (a path or builtin:...), root `source`
  /// The program's and libraries' versions, name → version, root `software_<name>`.
  std::map<std::string, std::string> software;
};

/// Writes `mesh`, which every rank of `comm` holds whole, as an HDF5 scene file: each rank writes
/// a slab of every dataset. Under a temporary name renamed into place once complete, so `path`
/// holds a whole scene or is left as it was. Throws Error(exit_code::kFailure) naming the file
/// on every rank. Collective.
void writeSceneFile(MPI_Comm comm, const std::string& path, const Mesh& mesh,
                    const SceneFileAttributes& attributes);

}  // namespace radiosity
