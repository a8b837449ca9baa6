// Refusing work that cannot fit, before it is attempted: a mesh that would exhaust the node's
// memory ends in bad_alloc (or the kernel's OOM killer) after minutes of refining.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

namespace radiosity::run {

/// What a patch costs while it is meshed: the mesh itself (about 84 bytes per triangle) and the
/// refinement's copy of it.
inline constexpr double kMeshBytesPerPatch = 200;

/// Throws Error(exit_code::kUsage) when the patches the options ask for (`patches`, or at least
/// totalArea / maxArea) would not fit in this node's memory, every rank on the node holding the
/// whole mesh; the message says how much they would need and which option to change
/// (`option`). Collective on `comm`.
void checkMeshFits(MPI_Comm comm, double totalArea, int64_t inputTriangles, int64_t patches,
                   double maxArea, const std::string& option);

/// What a nonzero of F costs at the peak of a solve: F's one store (12 bytes: a double and a
/// 32-bit column, lent to PETSc as its matrix), and a little over it for what else grows with F
/// and the rays, as bench/memory_per_nonzero.sh measures it.
inline constexpr double kBytesPerNonzero = 19;
/// The same with F's values in single precision (8 bytes a nonzero in the store): 4 fewer, as
/// measured (bench/memory_per_nonzero.sh, the Cornell box: 16.5 B in double, 12.9 in single).
inline constexpr double kBytesPerSingleNonzero = 15;

/// The memory of the job's nodes, each counted once: its physical memory or the job's limit
/// there, whichever is less (run/node_memory.h). Collective on `comm`.
double jobMemoryBytes(MPI_Comm comm);

/// The most patches whose F (at most columnsPerRow nonzeros a row, `bytesPerNonzero` each:
/// kBytesPerNonzero or kBytesPerSingleNonzero) fits in half of jobMemoryBytes(): the default
/// bound of adaptive refinement. From the nodes' memory alone, not from how many ranks share a
/// node, so that it is the same on 1 or 7 ranks of one node. Collective on `comm`.
int64_t patchesThatFit(MPI_Comm comm, int64_t columnsPerRow, double bytesPerNonzero);

/// Throws Error(exit_code::kUsage) when F may not fit in this node's memory: each row holds at
/// most min(patches, columnsPerRow) nonzeros (a sample's rays hit distinct patches at worst,
/// which large closed scenes approach), the node's ranks own their share of the rows and each
/// holds the whole mesh; a nonzero costs `bytesPerNonzero`. Says how much it may need and what to
/// change. Collective on `comm`.
void checkFormFactorsFit(MPI_Comm comm, int64_t patches, int64_t columnsPerRow,
                         double bytesPerNonzero, const std::string& rays);

}  // namespace radiosity::run
