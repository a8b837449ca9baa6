// Refusing work that cannot fit, before it is attempted: a mesh that would exhaust the node's
// memory ends in bad_alloc (or the kernel's OOM killer) after minutes of refining.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

namespace radiosity::jobs {

/// What a patch costs while it is meshed: the mesh itself (about 84 bytes per triangle) and the
/// refinement's copy of it.
inline constexpr double kMeshBytesPerPatch = 200;

/// Throws Error(exit_code::kUsage) when the patches the options ask for (`patches`, or at least
/// totalArea / maxArea) would not fit in this node's memory, every rank on the node holding the
/// whole mesh; the message says how much they would need and which option to change
/// (`option`). Collective on `comm`.
void checkMeshFits(MPI_Comm comm, double totalArea, int64_t inputTriangles, int64_t patches,
                   double maxArea, const std::string& option);

}  // namespace radiosity::jobs
