// The radiosity under hierarchical transport (hierarchy/): B = E + ρ ∘ (D + T (B − E)), with D
// each patch's light straight from the emitters and T = push · links · pull the transport of the
// reflected light, solved by PETSc's GMRES on the operator I − diag(ρ) T as a shell over the
// links (hierarchy/block_transport.h), the three channels as one system interleaved patch by
// patch, so that each product reads the links once for all three. Not yet a transport of `radiosity
// solve`: its checkpoints, rounds, error estimate and outputs still take the flat F
// (docs/design/hierarchy.md).
#pragma once

#include <petscsys.h>

#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "hierarchy/block_transport.h"

namespace radiosity::solve {

/// One rank's patches and what the system needs of them, per owned patch.
struct HierarchicalSystem {
  hierarchy::BlockTransport& transport;
  const std::vector<Rgb>& reflectance;
  const std::vector<Rgb>& emission;
  const std::vector<Rgb>& direct;  ///< D (hierarchy::LinkedRows::direct)
};

struct HierarchicalSolution {
  std::vector<Rgb> radiosity;  ///< B per owned patch
  int64_t iterations = 0;      ///< GMRES's
  int64_t transports = 0;      ///< applications of T
};

/// Solves the channels to the relative residual ‖b − A B‖ ≤ rtol ‖b‖ (b = E + ρ ∘ (D − T E),
/// the three channels' vectors as one), from B = b. PETSc options with the prefix "hierarchical_"
/// reach the solver. Collective.
PetscErrorCode solveHierarchical(MPI_Comm comm, const HierarchicalSystem& system, double rtol,
                                 HierarchicalSolution* solution);

}  // namespace radiosity::solve
