// Private to io/store: the result file's /display group, the mesh a viewer shows B smooth on
// (core/corner_radiosity.h DisplayMesh). Written by the result writer; the XDMF sidecar
// (io/store/xdmf.h) points ParaView at it.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>

#include "core/mesh.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/result.h"

namespace radiosity {

/// The display mesh is built a chunk of this many consecutive patches at a time, by the rank
/// owning the chunk's first patch: vertices are shared within a chunk (a chunk's border repeats
/// the few vertices it shares with the next), so the mesh is the same on any number of ranks and
/// no rank holds more of it than its own chunks, nor any array of B of the whole scene.
inline constexpr int64_t kDisplayChunk = int64_t{1} << 16;

/// Builds the display mesh of this rank's chunks (B of their neighbours from the ranks owning
/// them) and writes /display/{vertices,triangles,radiosity}, the chunks' vertices one after the
/// other; B with the first `channels` of its channels (3, or 1 for a thermal run). With 3, also
/// /display/luminance_tonemapped: each vertex's luminance Y as Y / (Y + midpoint), the midpoint
/// (its attribute) the area-weighted geometric mean of the luminance of the patches that reflect
/// and do not emit; the same bits on any number of ranks. Collective; failures end in `steps`.
void writeDisplayMesh(h5::CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                      const Mesh& patches, const LocalSolution& local, int channels = 3);

}  // namespace radiosity
