// Private to io/store: what the result writer checks of its arguments before it creates the
// file, on every rank together.
#pragma once

#include <mpi.h>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/result.h"

namespace radiosity {

/// Whether any rank has a hidden patch (then /patches/hidden is written). Collective.
int anyHiddenPatch(MPI_Comm comm, const LocalSolution& local);

/// Checks what the ranks hold before anything is created, so that bad arguments fail on all ranks
/// together: the patch blocks must tile [0, np) in rank order, the mesh must be the same size
/// everywhere and consistent, and this rank's triangles must index existing vertices. If any rank
/// has a radiosity stderr, every rank must have one row of it per patch it owns, each value finite
/// and ≥ 0 (and likewise the discretisation error, finite); hidden flags and rows of F (`rows`
/// or F's `store`, at most one), where given, must match the patches. Returns whether
/// /patches/radiosity_stderr is to be written (the same on every rank). Collective.
bool checkResultArguments(h5::CollectiveSteps& steps, MPI_Comm comm, const Mesh& patches,
                          const LocalSolution& local, const SparseRows* rows,
                          const SplitRows* store = nullptr);

}  // namespace radiosity
