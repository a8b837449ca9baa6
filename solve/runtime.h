// The solve's runtime: MPI and PETSc started and ended in order, the -log_view stages, the
// PETSc options checked before any work, and the heap handed back between stages.
#pragma once

#include <string>
#include <vector>

namespace radiosity::solve {

/// Gives glibc back its use of mmap for large blocks and its return of freed memory, which a
/// library loaded with PETSc turns off (the Runtime calls it first).
void returnFreedMemory();
/// Hands the heap's free pages back to the system (between stages and before the error
/// estimates, not during sampling).
void releaseFreedHeap();

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

/// The PETSc options given but never queried (PETSc's -options_left): misspelt, or meant for a
/// solver that did not run. Collective.
std::vector<std::string> unusedPetscOptions();

/// Refuses (exit code 2) PETSc options that the solve's KSP could not be set up with: an unknown
/// -ksp_type or -pc_type, a value that is not a number. Tried on a one-row system before any
/// work, on each rank alone (every rank has the same options).
void checkKrylovOptions();

}  // namespace radiosity::solve
