// Private to solve/: what every channel's solve works in, the one stored M = diag(w) F and its
// full-length vectors, and per-row values moved in and out of PETSc vectors.
#pragma once

#include <petscmat.h>

#include <vector>

#include "core/vec3.h"
#include "io/store/result.h"
#include "solve/petsc_handles.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

/// Everything the channels share while they are solved: the stored matrix and its vectors,
/// owned: they go with the object, on every path out of the solve.
struct SharedSystem {
  /// F's one store, when M was made on its arrays (lendRows): declared before M, so that it goes
  /// after it.
  formfactor::SplitRows lent;
  OwnedMat M;
  OwnedVec rho, E, B, H, weight, area;
  OwnedVec emitter;  ///< 1 where a patch emits, else 0
};

/// Assembles M = diag(w) F from `rows` (w = the areas for the symmetric form, else 1) and
/// creates the vectors, filling w, area and emitter. F's one store with w = 1 is moved into
/// s->lent and M made on its arrays, without a copy (in single precision: a shell matrix,
/// solve/single_precision_matrix.h), except a single-precision store for a solver that needs
/// M's entries in place (`explicitMatrix`: gauss-seidel), which gets an AIJ copy. Checks that the
/// ranks' rows add up to `globalCount` patches. Collective.
PetscErrorCode setUpSharedSystem(FormFactorRows& rows, int64_t globalCount,
                                 const std::vector<double>& localArea,
                                 const std::vector<Rgb>& emission, bool symmetricForm,
                                 bool explicitMatrix, SharedSystem* s);

/// Copies channel c of per-row triples into a PETSc vector.
PetscErrorCode fillChannel(Vec v, const std::vector<Rgb>& values, int c);
PetscErrorCode fillValues(Vec v, const std::vector<double>& values);
/// Channel c of per-row triples from a PETSc vector.
PetscErrorCode readChannel(Vec v, std::vector<Rgb>& values, int c);

/// y = F x = diag(1/w) M x; with x = B, the flux arriving per unit area H.
PetscErrorCode multiplyF(Mat M, Vec weight, Vec x, Vec y);

/// B and H = F B of channel c (in s.B) into the solution.
PetscErrorCode readChannelResults(const SharedSystem& s, int c, LocalSolution& solution);

/// Copies channel `from` into channel `to` of per-row triples.
void copyChannel(std::vector<Rgb>& values, int from, int to);

}  // namespace radiosity::solve
