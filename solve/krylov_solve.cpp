// The PETSc solvers of --solver (all but southwell). Jacobi, GMRES and Chebyshev iterate on
// the shell operator A = I − diag(s) M_R (no second matrix); Gauss-Seidel and CG need the
// entries of their matrix, so they turn M_R in place into K = diag(1/s) − M_R = diag(1/s) A
// (symmetric for CG, where M = diag(area) F is) and undo it exactly afterwards.
#include <cmath>
#include <cstdio>
#include <string>

#include "solve/channel_system.h"

namespace radiosity::solve {

namespace {

struct MonitorContext {
  const HistoryRecorder* recorder;
  int64_t offset;  ///< iterations of earlier rounds
};

PetscErrorCode recordIteration(KSP, PetscInt iteration, PetscReal residualNorm, void* raw) {
  const auto* context = static_cast<const MonitorContext*>(raw);
  context->recorder->record(context->offset + iteration, residualNorm);
  return 0;
}

// PETSc's default test, then the caller's safe point (collective: every rank runs the test at
// every iteration). An interruption ends KSPSolve as if by the iteration limit, which makes
// GMRES build its iterate; the action tells the two apart.
struct StopTest {
  void* defaultContext = nullptr;
  const SafePoint* safePoint = nullptr;
  SafePointAction action = SafePointAction::kContinue;
};

PetscErrorCode convergedOrStopped(KSP ksp, PetscInt iteration, PetscReal norm,
                                  KSPConvergedReason* reason, void* raw) {
  auto* test = static_cast<StopTest*>(raw);
  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, iteration, norm, reason, test->defaultContext));
  if (*reason == KSP_CONVERGED_ITERATING && iteration > 0 && *test->safePoint) {
    test->action = (*test->safePoint)();
    if (test->action != SafePointAction::kContinue) *reason = KSP_CONVERGED_ITS;
  }
  PetscFunctionReturn(0);
}

bool needsExplicitMatrix(Solver solver) {
  return solver == Solver::kGaussSeidel || solver == Solver::kCg;
}

PetscErrorCode configure(KSP ksp, Solver solver, const ChannelSystem& system) {
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  // Point Jacobi and local SOR do not change with the rank count (block preconditioners do).
  PetscCall(PCSetType(pc, PCJACOBI));
  if (solver == Solver::kJacobi) {
    PetscCall(KSPSetType(ksp, KSPRICHARDSON));  // -ksp_richardson_scale relaxes it
  } else if (solver == Solver::kGaussSeidel) {
    PetscCall(KSPSetType(ksp, KSPRICHARDSON));
    PetscCall(PCSetType(pc, PCSOR));
    PetscCall(PCSORSetSymmetric(pc, SOR_LOCAL_FORWARD_SWEEP));
  } else if (solver == Solver::kCg) {
    PetscCall(KSPSetType(ksp, KSPCG));
    PetscCall(KSPSetComputeSingularValues(ksp, PETSC_TRUE));
  } else if (solver == Solver::kChebyshev) {
    PetscCall(KSPSetType(ksp, KSPCHEBYSHEV));
    if (system.contraction < 1) {
      // The Jacobi-preconditioned operator is I − D⁻¹ diag(s) M, whose spectral radius of the
      // second term is at most q: its eigenvalues lie within 1 ∓ q.
      PetscCall(KSPChebyshevSetEigenvalues(ksp, 1 + system.contraction, 1 - system.contraction));
    } else {
      PetscCall(KSPChebyshevEstEigSet(ksp, PETSC_DECIDE, PETSC_DECIDE, PETSC_DECIDE, PETSC_DECIDE));
    }
  } else {
    PetscCall(KSPSetType(ksp, KSPGMRES));
    PetscCall(KSPSetPCSide(ksp, PC_RIGHT));  // its residual is then the true one
    PetscCall(KSPSetComputeSingularValues(ksp, PETSC_TRUE));
  }
  PetscCall(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
  PetscCall(KSPSetFromOptions(ksp));  // -ksp_* and -pc_* have the last word
  PetscFunctionReturn(0);
}

// M_R ↔ K = diag(1/s) − M_R in place. Negation is exact and the diagonal is saved, so the
// shared matrix comes back bit for bit.
PetscErrorCode toExplicitForm(ChannelSystem& system, Vec savedDiagonal) {
  Vec diagonal;
  PetscFunctionBeginUser;
  PetscCall(MatGetDiagonal(system.matrix, savedDiagonal));
  PetscCall(VecDuplicate(system.scale, &diagonal));
  PetscCall(VecCopy(system.scale, diagonal));
  PetscCall(VecReciprocal(diagonal));
  PetscCall(VecAXPY(diagonal, -1.0, savedDiagonal));  // 1/s − M_ii
  PetscCall(MatScale(system.matrix, -1.0));
  PetscCall(MatDiagonalSet(system.matrix, diagonal, INSERT_VALUES));
  PetscCall(VecDestroy(&diagonal));
  PetscFunctionReturn(0);
}

PetscErrorCode fromExplicitForm(ChannelSystem& system, Vec savedDiagonal) {
  PetscFunctionBeginUser;
  PetscCall(VecScale(savedDiagonal, -1.0));
  PetscCall(MatDiagonalSet(system.matrix, savedDiagonal, INSERT_VALUES));
  PetscCall(MatScale(system.matrix, -1.0));
  PetscFunctionReturn(0);
}

std::string hint(Solver solver, double contraction) {
  char text[200];
  if (solver == Solver::kJacobi || solver == Solver::kGaussSeidel) {
    std::snprintf(text, sizeof text,
                  " (%s needs about 1/(1 - q) sweeps, q = %.6g here: use --solver gmres or cg, "
                  "or raise -ksp_max_it)",
                  solverName(solver), contraction);
  } else {
    std::snprintf(text, sizeof text, " (raise -ksp_max_it or loosen --rtol)");
  }
  return text;
}

}  // namespace

PetscErrorCode solveWithKsp(ChannelSystem& system, Solver solver, double rtol,
                            const HistoryRecorder& history, const SafePoint& safePoint,
                            WorkCount& work, ChannelOutcome& outcome) {
  MPI_Comm comm;
  Mat A = nullptr;
  Vec b, r, savedDiagonal = nullptr;
  KSP ksp;
  const bool explicitForm = needsExplicitMatrix(solver);
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(system.matrix), &comm));
  PetscCall(VecDuplicate(system.rhs, &b));
  PetscCall(VecDuplicate(system.rhs, &r));
  if (explicitForm) {
    PetscCall(VecDuplicate(system.rhs, &savedDiagonal));
    PetscCall(toExplicitForm(system, savedDiagonal));
    PetscCall(VecPointwiseDivide(b, system.rhs, system.scale));  // diag(1/s) b
    PetscCall(createCountingOperator(system.matrix, system.nonzeros, work, &A));
  } else {
    PetscCall(VecCopy(system.rhs, b));
    PetscCall(createShellOperator(system, work, &A));
  }
  PetscReal rhsNorm;
  PetscCall(VecNorm(b, NORM_2, &rhsNorm));
  const PetscReal target = rtol * system.emissionNorm;  // on ‖b − A x‖ of the unscaled system

  PetscCall(KSPCreate(comm, &ksp));
  // The preconditioner (SOR, Jacobi) sees K itself; A counts the products.
  PetscCall(KSPSetOperators(ksp, A, explicitForm ? system.matrix : A));
  PetscCall(configure(ksp, solver, system));
  HistoryRecorder recorder = history;
  recorder.normalise = explicitForm ? rhsNorm : system.emissionNorm;
  MonitorContext monitor{&recorder, history.firstIteration};
  PetscCall(KSPMonitorSet(ksp, recordIteration, &monitor, nullptr));
  StopTest test;
  test.safePoint = &safePoint;
  PetscCall(KSPConvergedDefaultCreate(&test.defaultContext));
  PetscCall(KSPSetConvergenceTest(ksp, convergedOrStopped, &test, nullptr));

  // KSP measures ‖b − A x‖ of the system it iterates on, relative to ‖b‖; the answer must
  // meet ‖E − A B‖ ≤ rtol ‖E‖. Start from the ratio of the two and tighten until it does.
  PetscReal kspRtol = rhsNorm > 0 ? std::min<PetscReal>(0.5, target / rhsNorm) : rtol;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscReal trueResidual = 0;
  for (int round = 0; round < 4; ++round) {
    PetscCall(KSPSetTolerances(ksp, kspRtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
    PetscCall(KSPSolve(ksp, b, system.solution));
    PetscInt iterations;
    PetscCall(KSPGetIterationNumber(ksp, &iterations));
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    outcome.iterations += iterations;
    monitor.offset += iterations;
    if (solver == Solver::kGaussSeidel) {  // one sweep over K per iteration, inside PCSOR
      work.matrixProducts += iterations;
      work.nonzeroProducts += static_cast<int64_t>(iterations) * system.nonzeros;
    }
    if (test.action != SafePointAction::kContinue) {
      outcome.interrupted = test.action;  // the iterate is in system.solution
      break;
    }
    // The true residual of the unscaled system: r = s ⊙ (b' − K x) or b − A x.
    PetscCall(MatMult(A, system.solution, r));
    PetscCall(VecAYPX(r, -1.0, b));
    if (explicitForm) PetscCall(VecPointwiseMult(r, r, system.scale));
    PetscCall(VecNorm(r, NORM_2, &trueResidual));
    if (reason < 0 || !std::isfinite(trueResidual) || trueResidual <= target) break;
    kspRtol *= 0.5 * target / trueResidual;
  }
  const double relative =
      system.emissionNorm > 0 ? trueResidual / system.emissionNorm : trueResidual;
  if (outcome.interrupted != SafePointAction::kContinue) {
    // nothing to judge yet
  } else if (!std::isfinite(relative)) {
    outcome.failure = "its iterate is not finite (NaN or Inf)";
  } else if (reason < 0) {
    char text[200];
    std::snprintf(
        text, sizeof text, "did not converge: %s after %lld iterations, relative residual %.3g",
        KSPConvergedReasons[reason], static_cast<long long>(outcome.iterations), relative);
    outcome.failure = text + hint(solver, system.contraction);
  } else if (trueResidual > target) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "stopped at relative residual %.3g, above --rtol %.3g: round-off sets the floor "
                  "here; loosen --rtol",
                  relative, rtol);
    outcome.failure = text;
  }
  outcome.converged = outcome.failure.empty();

  if ((solver == Solver::kGmres || solver == Solver::kCg) && outcome.converged &&
      outcome.interrupted == SafePointAction::kContinue) {
    PetscReal largest = 0, smallest = 0;
    PetscCall(KSPComputeExtremeSingularValues(ksp, &largest, &smallest));
    if (smallest > 0) {
      outcome.conditionEstimate = largest / smallest;
      outcome.conditionSource = solver == Solver::kCg
                                    ? "cg's Lanczos values of the Jacobi-scaled operator"
                                    : "gmres's Hessenberg singular values (Jacobi-scaled)";
    }
  }
  PetscCall(KSPDestroy(&ksp));
  PetscCall(KSPConvergedDefaultDestroy(test.defaultContext));
  PetscCall(MatDestroy(&A));
  if (explicitForm) {
    PetscCall(fromExplicitForm(system, savedDiagonal));
    PetscCall(VecDestroy(&savedDiagonal));
  }
  PetscCall(VecDestroy(&b));
  PetscCall(VecDestroy(&r));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
