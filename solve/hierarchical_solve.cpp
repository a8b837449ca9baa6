// GMRES over the hierarchical transport (hierarchical_solve.h).
#include "solve/hierarchical_solve.h"

#include <petscksp.h>

#include "solve/petsc_handles.h"

namespace radiosity::solve {

namespace {

constexpr int kChannels = 3;

// What the shell's product reads: A x = x − ρ ∘ T x, the channels interleaved patch by patch.
struct Operator {
  hierarchy::BlockTransport* transport = nullptr;
  Vec rho = nullptr;
  int64_t* transports = nullptr;
};

// y = T x, every channel in one pass over the links.
PetscErrorCode applyTransport(hierarchy::BlockTransport& transport, Vec x, Vec y) {
  const PetscScalar* in;
  PetscScalar* out;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(x, &in));
  PetscCall(VecGetArray(y, &out));
  const PetscErrorCode applied = transport.apply(in, out, kChannels);
  PetscCall(VecRestoreArray(y, &out));
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscCall(applied);
  PetscFunctionReturn(0);
}

PetscErrorCode multiply(Mat A, Vec x, Vec y) {
  Operator* op;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &op));
  PetscCall(applyTransport(*op->transport, x, y));
  ++*op->transports;
  PetscCall(VecPointwiseMult(y, op->rho, y));
  PetscCall(VecAYPX(y, -1.0, x));  // y = x − ρ ∘ T x
  PetscFunctionReturn(0);
}

PetscErrorCode fill(Vec v, const std::vector<Rgb>& values) {
  PetscScalar* a;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &a));
  for (size_t i = 0; i < values.size(); ++i)
    for (int c = 0; c < kChannels; ++c) a[i * kChannels + c] = values[i][c];
  PetscCall(VecRestoreArray(v, &a));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode solveHierarchical(MPI_Comm comm, const HierarchicalSystem& system, double rtol,
                                 HierarchicalSolution* solution) {
  const auto local = static_cast<PetscInt>(system.emission.size() * kChannels);
  OwnedVec rho, emission, direct, rhs, b;
  OwnedMat A;
  OwnedKsp ksp;
  Operator op{&system.transport, nullptr, &solution->transports};
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, local, PETSC_DETERMINE, rho.out()));
  PetscCall(VecSetBlockSize(rho, kChannels));
  PetscCall(VecDuplicate(rho, emission.out()));
  PetscCall(VecDuplicate(rho, direct.out()));
  PetscCall(VecDuplicate(rho, rhs.out()));
  PetscCall(VecDuplicate(rho, b.out()));
  op.rho = rho;
  PetscInt global;
  PetscCall(VecGetSize(rho, &global));
  PetscCall(MatCreateShell(comm, local, local, global, global, &op, A.out()));
  PetscCall(MatShellSetOperation(A, MATOP_MULT, reinterpret_cast<void (*)(void)>(multiply)));
  PetscCall(fill(rho, system.reflectance));
  PetscCall(fill(emission, system.emission));
  PetscCall(fill(direct, system.direct));
  // b = E + ρ ∘ (D − T E): the direct light in, and the emitters' own B − E = 0 at the start.
  PetscCall(applyTransport(system.transport, emission, rhs));
  ++solution->transports;
  PetscCall(VecAYPX(rhs, -1.0, direct));
  PetscCall(VecPointwiseMult(rhs, rho, rhs));
  PetscCall(VecAXPY(rhs, 1.0, emission));
  PetscCall(VecCopy(rhs, b));

  PetscCall(KSPCreate(comm, ksp.out()));
  PetscCall(KSPSetOptionsPrefix(ksp, "hierarchical_"));
  PetscCall(KSPSetType(ksp, KSPGMRES));
  // Ten vectors of 3n, not PETSc's 30: the rooms need 18 iterations with them against 17 with
  // 30 (and 42 for Richardson), and 30 would be 3.6 GB a rank at 10^7 patches.
  PetscCall(KSPGMRESSetRestart(ksp, 10));
  PC pc;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCNONE));  // (A's diagonal is 1 but for a patch's link to itself)
  PetscCall(KSPSetTolerances(ksp, rtol, 0.0, PETSC_DEFAULT, 10000));
  PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(KSPSolve(ksp, rhs, b));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCheck(reason > 0, comm, PETSC_ERR_NOT_CONVERGED,
             "the hierarchical system did not converge (%s)", KSPConvergedReasons[reason]);
  PetscInt iterations;
  PetscCall(KSPGetIterationNumber(ksp, &iterations));
  solution->iterations = iterations;
  const PetscScalar* x;
  PetscCall(VecGetArrayRead(b, &x));
  solution->radiosity.assign(system.emission.size(), Rgb{0, 0, 0});
  for (size_t i = 0; i < system.emission.size(); ++i)
    for (int c = 0; c < kChannels; ++c) solution->radiosity[i][c] = x[i * kChannels + c];
  PetscCall(VecRestoreArrayRead(b, &x));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
