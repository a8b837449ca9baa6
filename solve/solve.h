// solve: assembles F once as a PETSc MPIAIJ matrix and solves (I − diag(ρ_c) F) B_c = E_c per
// colour channel with a PETSc KSP. PETSc stays behind this header. Collective on the
// communicator PETSc was initialised with (PETSC_COMM_WORLD).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/io.h"

namespace radiosity::solve {

/// Starts MPI and PETSc and ends them in the right order (RAII, like deal.II's
/// MPI_InitFinalize). `argv` holds the program name and the PETSc options only.
class Runtime {
 public:
  Runtime(int argc, char** argv);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;
};

/// A named stage of the -log_view report, pushed for the lifetime of the object.
class ScopedStage {
 public:
  explicit ScopedStage(const char* name);
  ~ScopedStage();
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;
};

/// PETSc's options database says whether `name` (e.g. "-log_view") was given.
bool hasPetscOption(const char* name);

struct Options {
  std::string solver = "gmres";  ///< "jacobi" (Richardson + Jacobi) or "gmres"
  double rtol = 1e-10;           ///< relative residual at which each channel stops
};

struct Report {
  int64_t iterations = 0;  ///< summed over channels
  double residual = 0;  ///< largest final relative residual ‖E − A B‖/‖E‖ over channels
  bool converged = true;
  int channelsSolved = 0;
};

/// Throws Error(exit_code::kNumerical) when a channel does not converge or the system is
/// unphysical. `reflectance`/`emission` hold this rank's rows (those of `rows`).
LocalSolution solveRadiosity(const formfactor::SparseRows& rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const Options& options, Report& report);

}  // namespace radiosity::solve
