// solve: assembles F once as a PETSc MPIAIJ matrix and solves (I − diag(ρ_c) F) B_c = E_c per
// colour channel with a PETSc KSP. PETSc stays behind this header. Collective on the
// communicator PETSc was initialised with (PETSC_COMM_WORLD).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "solve/repair.h"
#include "solve/runtime.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

/// The solver a scene should use when the user names none, and why.
struct SolverChoice {
  Solver solver = Solver::kGmres;
  std::string reason;
};

/// Picks from the largest row-scaled reflectance q = max_i ρ_i Σ_j F_ij and from whether F is
/// (made) reciprocal. Collective; every rank gets the same choice.
/// `rowSums`: this rank's Σ_j |F_ij| (formfactor::rowSums of F as sampled, all entries ≥ 0).
SolverChoice chooseSolver(const std::vector<double>& rowSums, const std::vector<Rgb>& reflectance,
                          bool reciprocal, MPI_Comm comm = MPI_COMM_WORLD);

/// Throws Error(exit_code::kNumerical) when a channel does not converge or the system is
/// unphysical. `reflectance`, `emission` and `area` hold this rank's rows (those of `rows`).
/// `rows` is freed as soon as PETSc holds F, so that F is stored once during the solve: move
/// it in unless it is needed afterwards.
LocalSolution solveRadiosity(FormFactorRows rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const std::vector<double>& area, const Options& options,
                             Report& report);

}  // namespace radiosity::solve
