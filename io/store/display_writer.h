// Private to io/store: the result file's /display group, the mesh a viewer shows B smooth on
// (core/corner_radiosity.h DisplayMesh). Written by the result writer; the XDMF sidecar
// (io/store/xdmf.h) points ParaView at it.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include "core/mesh.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/result.h"

namespace radiosity {

/// Gathers B on rank 0, which builds the display mesh and writes /display/{vertices,triangles,
/// radiosity} whole (the others write no rows). Collective; failures end in `steps`.
void writeDisplayMesh(h5::CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                      const Mesh& patches, const LocalSolution& local);

}  // namespace radiosity
