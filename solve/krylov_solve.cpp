// The PETSc solvers of --solver (all but southwell). Jacobi, GMRES and Chebyshev iterate on
// the shell operator A = I − diag(s) M_R (no second matrix); Gauss-Seidel and CG need the
// entries of their matrix, so they turn M_R in place into K = diag(1/s) − M_R = diag(1/s) A
// (symmetric for CG, where M = diag(area) F is) and undo it exactly afterwards, on every path
// out (a ScopeGuard): the matrix is shared by every channel and by the caller.
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "solve/channel_system.h"
#include "solve/petsc_handles.h"

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
  void* defaultContext = nullptr;  ///< owned: PETSc's default test's context
  const SafePoint* safePoint = nullptr;
  SafePointAction action = SafePointAction::kContinue;
  StopTest() = default;
  StopTest(const StopTest&) = delete;
  StopTest& operator=(const StopTest&) = delete;
  ~StopTest() {
    if (defaultContext) PetscCallVoid(KSPConvergedDefaultDestroy(defaultContext));
  }
};

PetscErrorCode convergedOrStopped(KSP ksp, PetscInt iteration, PetscReal norm,
                                  KSPConvergedReason* reason, void* raw) {
  auto* test = static_cast<StopTest*>(raw);
  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, iteration, norm, reason, test->defaultContext));
  if (*reason == KSP_CONVERGED_ITERATING && iteration > 0 && *test->safePoint) {
    // PETSc is C: an exception must not unwind through KSPSolve's frames. It ends the solve as
    // a PETSc error that names it, which the caller's check() turns back into an exception.
    try {
      test->action = (*test->safePoint)();
    } catch (const std::exception& e) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER, "at a safe point in the solve: %s", e.what());
    }
    if (test->action != SafePointAction::kContinue) *reason = KSP_CONVERGED_ITS;
  }
  PetscFunctionReturn(0);
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
// shared matrix comes back bit for bit. *converted is set once M_R is negated: from there on,
// fromExplicitForm takes it back (setting the diagonal again is harmless if it was not yet).
PetscErrorCode toExplicitForm(ChannelSystem& system, Vec savedDiagonal, bool* converted) {
  OwnedVec diagonal;
  PetscFunctionBeginUser;
  PetscCall(MatGetDiagonal(system.matrix, savedDiagonal));
  PetscCall(VecDuplicate(system.scale, diagonal.out()));
  PetscCall(VecCopy(system.scale, diagonal));
  PetscCall(VecReciprocal(diagonal));
  PetscCall(VecAXPY(diagonal, -1.0, savedDiagonal));  // 1/s − M_ii
  PetscCall(MatScale(system.matrix, -1.0));
  *converted = true;
  PetscCall(MatDiagonalSet(system.matrix, diagonal, INSERT_VALUES));
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

// One channel's (or block's) KSP solve: the operator, the KSP configured with the monitor and
// the stop test, the rounds until the true residual meets the target, and the verdict.
class KrylovSolve {
 public:
  KrylovSolve(ChannelSystem& system, Solver solver, WorkCount& work)
      : system_(system), solver_(solver), explicitForm_(needsExplicitMatrix(solver)), work_(work) {}

  PetscErrorCode run(double rtol, const HistoryRecorder& history, const SafePoint& safePoint,
                     ChannelOutcome& outcome) {
    // Declared before the guard, so that the saved diagonal outlives the undo.
    OwnedVec savedDiagonal;
    bool converted = false;
    ScopeGuard restore([&]() -> PetscErrorCode {
      return converted ? fromExplicitForm(system_, savedDiagonal) : PetscErrorCode(0);
    });
    PetscFunctionBeginUser;
    PetscCall(VecDuplicate(system_.rhs, b_.out()));
    PetscCall(VecDuplicate(system_.rhs, r_.out()));
    if (explicitForm_) {
      PetscCall(VecDuplicate(system_.rhs, savedDiagonal.out()));
      PetscCall(toExplicitForm(system_, savedDiagonal, &converted));
      PetscCall(VecPointwiseDivide(b_, system_.rhs, system_.scale));  // diag(1/s) b
      PetscCall(createCountingOperator(system_.matrix, system_.nonzeros, work_, A_.out()));
    } else {
      PetscCall(VecCopy(system_.rhs, b_));
      PetscCall(createShellOperator(system_, work_, A_.out()));
    }
    PetscCall(VecNorm(b_, NORM_2, &rhsNorm_));
    target_ = rtol * system_.emissionNorm;  // on ‖b − A x‖ of the unscaled system
    HistoryRecorder recorder = history;
    recorder.normalise = explicitForm_ ? rhsNorm_ : system_.emissionNorm;
    MonitorContext monitor{&recorder, history.firstIteration};
    test_.safePoint = &safePoint;
    PetscCall(createKsp(monitor));
    PetscCall(iterate(rtol, monitor, outcome));
    judge(rtol, outcome);
    PetscCall(estimateCondition(outcome));
    ksp_.reset();
    A_.reset();
    PetscCall(restore.undoNow());
    PetscFunctionReturn(0);
  }

 private:
  PetscErrorCode createKsp(MonitorContext& monitor) {
    MPI_Comm comm;
    PetscFunctionBeginUser;
    PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(system_.matrix.get()), &comm));
    PetscCall(KSPCreate(comm, ksp_.out()));
    // The preconditioner (SOR, Jacobi) sees K itself; A counts the products.
    PetscCall(KSPSetOperators(ksp_, A_, explicitForm_ ? system_.matrix.get() : A_.get()));
    PetscCall(configure(ksp_, solver_, system_));
    PetscCall(KSPMonitorSet(ksp_, recordIteration, &monitor, nullptr));
    PetscCall(KSPConvergedDefaultCreate(&test_.defaultContext));
    PetscCall(KSPSetConvergenceTest(ksp_, convergedOrStopped, &test_, nullptr));
    PetscFunctionReturn(0);
  }

  // KSP measures ‖b − A x‖ of the system it iterates on, relative to ‖b‖; the answer must
  // meet ‖E − A B‖ ≤ rtol ‖E‖. Start from the ratio of the two and tighten until it does.
  PetscErrorCode iterate(double rtol, MonitorContext& monitor, ChannelOutcome& outcome) {
    PetscFunctionBeginUser;
    PetscReal kspRtol = rhsNorm_ > 0 ? std::min<PetscReal>(0.5, target_ / rhsNorm_) : rtol;
    for (int round = 0; round < 4; ++round) {
      PetscCall(KSPSetTolerances(ksp_, kspRtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
      PetscCall(KSPSolve(ksp_, b_, system_.solution));
      PetscInt iterations;
      PetscCall(KSPGetIterationNumber(ksp_, &iterations));
      PetscCall(KSPGetConvergedReason(ksp_, &reason_));
      outcome.iterations += iterations;
      monitor.offset += iterations;
      if (solver_ == Solver::kGaussSeidel) {  // one sweep over K per iteration, inside PCSOR
        work_.matrixProducts += iterations;
        work_.nonzeroProducts += static_cast<int64_t>(iterations) * system_.nonzeros;
      }
      if (test_.action != SafePointAction::kContinue) {
        outcome.interrupted = test_.action;  // the iterate is in system.solution
        break;
      }
      // The true residual of the unscaled system: r = s ⊙ (b' − K x) or b − A x.
      PetscCall(MatMult(A_, system_.solution, r_));
      PetscCall(VecAYPX(r_, -1.0, b_));
      if (explicitForm_) PetscCall(VecPointwiseMult(r_, r_, system_.scale));
      PetscCall(VecNorm(r_, NORM_2, &trueResidual_));
      if (reason_ < 0 || !std::isfinite(trueResidual_) || trueResidual_ <= target_) break;
      kspRtol *= 0.5 * target_ / trueResidual_;
    }
    PetscFunctionReturn(0);
  }

  // Why the solve did not converge, with the option to change, or nothing.
  void judge(double rtol, ChannelOutcome& outcome) const {
    const double relative =
        system_.emissionNorm > 0 ? trueResidual_ / system_.emissionNorm : trueResidual_;
    if (outcome.interrupted != SafePointAction::kContinue) {
      // nothing to judge yet
    } else if (!std::isfinite(relative)) {
      outcome.failure = "its iterate is not finite (NaN or Inf)";
    } else if (reason_ < 0) {
      char text[200];
      std::snprintf(
          text, sizeof text, "did not converge: %s after %lld iterations, relative residual %.3g",
          KSPConvergedReasons[reason_], static_cast<long long>(outcome.iterations), relative);
      outcome.failure = text + hint(solver_, system_.contraction);
    } else if (trueResidual_ > target_) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "stopped at relative residual %.3g, above --rtol %.3g: round-off sets the "
                    "floor here; loosen --rtol",
                    relative, rtol);
      outcome.failure = text;
    }
    outcome.converged = outcome.failure.empty();
  }

  PetscErrorCode estimateCondition(ChannelOutcome& outcome) const {
    PetscFunctionBeginUser;
    if ((solver_ == Solver::kGmres || solver_ == Solver::kCg) && outcome.converged &&
        outcome.interrupted == SafePointAction::kContinue) {
      PetscReal largest = 0, smallest = 0;
      PetscCall(KSPComputeExtremeSingularValues(ksp_, &largest, &smallest));
      if (smallest > 0) {
        outcome.conditionEstimate = largest / smallest;
        outcome.conditionSource = solver_ == Solver::kCg
                                      ? "cg's Lanczos values of the Jacobi-scaled operator"
                                      : "gmres's Hessenberg singular values (Jacobi-scaled)";
      }
    }
    PetscFunctionReturn(0);
  }

  ChannelSystem& system_;
  const Solver solver_;
  const bool explicitForm_;
  WorkCount& work_;
  OwnedVec b_, r_;
  OwnedMat A_;
  StopTest test_;  // (before the KSP, which calls it until it is destroyed)
  OwnedKsp ksp_;
  PetscReal rhsNorm_ = 0, target_ = 0, trueResidual_ = 0;
  KSPConvergedReason reason_ = KSP_CONVERGED_ITERATING;
};

}  // namespace

PetscErrorCode solveWithKsp(ChannelSystem& system, Solver solver, double rtol,
                            const HistoryRecorder& history, const SafePoint& safePoint,
                            WorkCount& work, ChannelOutcome& outcome) {
  KrylovSolve solve(system, solver, work);
  return solve.run(rtol, history, safePoint, outcome);
}

}  // namespace radiosity::solve
