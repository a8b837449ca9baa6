// One rank's mesh on every rank. A scene file read by each rank on its own can differ between
// them (a file replaced while the ranks start: they then wait in different collectives for
// ever); read once and broadcast, every rank holds the same bytes' mesh.
#pragma once

#include <mpi.h>

#include "core/mesh.h"

namespace radiosity {

/// Replaces `mesh` on every rank of `comm` by rank 0's (every field). Collective.
void broadcastMesh(MPI_Comm comm, Mesh& mesh);

}  // namespace radiosity
