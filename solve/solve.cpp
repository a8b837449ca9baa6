// The PETSc adapter. F is assembled once (MPIAIJ, preallocated from the sparse rows, diagonal
// kept so the operator can be shifted in place); each channel turns a copy of it into
// I − diag(ρ_c) F and solves with the chosen KSP. PETSc-style functions below return
// PetscErrorCode; the C++ entry point turns failures into exceptions after cleaning up.
#include <petscksp.h>

#include <cmath>
#include <map>
#include <string>

#include "solve/assemble.h"
#include "solve/channel_plan.h"
#include "solve/solve.h"

namespace radiosity::solve {

namespace {

void check(PetscErrorCode code, const char* what) {
  if (code) {
    throw Error(exit_code::kFailure,
                std::string("PETSc failed in ") + what + " (error " + std::to_string(code) + ")");
  }
}

PetscErrorCode configureSolver(KSP ksp, const Options& options) {
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  if (options.solver == "jacobi") {
    // Richardson preconditioned by the diagonal is the seeds' (relaxed) Jacobi iteration;
    // -ksp_richardson_scale sets the relaxation.
    PetscCall(KSPSetType(ksp, KSPRICHARDSON));
  } else {
    PetscCall(KSPSetType(ksp, KSPGMRES));
  }
  // Point Jacobi is the same on any number of ranks (block preconditioners are not).
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(KSPSetTolerances(ksp, options.rtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
  PetscCall(KSPSetFromOptions(ksp));  // -ksp_* and -pc_* have the last word
  PetscFunctionReturn(0);
}

// Copies channel c of per-row triples into a PETSc vector.
PetscErrorCode fillChannel(Vec v, const std::vector<Rgb>& values, int c) {
  PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &array));
  for (size_t r = 0; r < values.size(); ++r) array[r] = values[r][c];
  PetscCall(VecRestoreArray(v, &array));
  PetscFunctionReturn(0);
}

PetscErrorCode readChannel(Vec v, std::vector<Rgb>& values, int c) {
  const PetscScalar* array;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(v, &array));
  for (size_t r = 0; r < values.size(); ++r) values[r][c] = array[r];
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscFunctionReturn(0);
}

struct ChannelFailure {
  std::string message;  ///< empty when every channel converged
};

PetscErrorCode solveChannels(const formfactor::SparseRows& rows, int64_t globalCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const Options& options, LocalSolution& solution, Report& report,
                             ChannelFailure& failure) {
  Mat F, A;
  KSP ksp;
  Vec rho, E, B, residual;
  PetscFunctionBeginUser;
  PetscCall(assembleRows(PETSC_COMM_WORLD, rows, nullptr, &F));
  PetscInt rowsInAll, columnsInAll;
  PetscCall(MatGetSize(F, &rowsInAll, &columnsInAll));
  PetscCheck(rowsInAll == globalCount, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
             "the ranks' rows add up to %" PetscInt_FMT " patches, not %" PetscInt_FMT, rowsInAll,
             static_cast<PetscInt>(globalCount));
  PetscCall(MatDuplicate(F, MAT_COPY_VALUES, &A));
  PetscCall(MatCreateVecs(F, &B, &E));
  PetscCall(VecDuplicate(E, &rho));
  PetscCall(VecDuplicate(E, &residual));
  PetscCall(KSPCreate(PETSC_COMM_WORLD, &ksp));

  // Leave out what the scene does not need: channels without reflection (B = E) and channels
  // equal to one already solved.
  const ChannelPlan plan = planChannels(PETSC_COMM_WORLD, rows, reflectance, emission);
  report.leftOut = plan.leftOut();
  for (int c = 0; c < 3 && failure.message.empty(); ++c) {
    const char* channelName = c == 0 ? "red" : (c == 1 ? "green" : "blue");
    if (plan.singular[c]) {
      failure.message = std::string("the ") + channelName +
                        " channel is singular: every patch of a closed scene reflects all the "
                        "light it gets (rho = 1), so I - F has no inverse; lower the reflectance";
      break;
    }
    if (plan.sameAs[c] >= 0) {
      for (size_t r = 0; r < solution.radiosity.size(); ++r) {
        solution.radiosity[r][c] = solution.radiosity[r][plan.sameAs[c]];
        solution.irradiance[r][c] = solution.irradiance[r][plan.sameAs[c]];
      }
      continue;
    }
    PetscCall(fillChannel(E, emission, c));
    if (plan.noReflection[c]) {  // B = E; H = F E all the same
      for (size_t r = 0; r < solution.radiosity.size(); ++r)
        solution.radiosity[r][c] = emission[r][c];
      PetscCall(MatMult(F, E, residual));
      PetscCall(readChannel(residual, solution.irradiance, c));
      continue;
    }
    PetscCall(fillChannel(rho, reflectance, c));
    // A = I − diag(ρ_c) F, rebuilt in place from F for each channel.
    PetscCall(MatCopy(F, A, SAME_NONZERO_PATTERN));
    PetscCall(MatDiagonalScale(A, rho, nullptr));
    PetscCall(MatScale(A, -1.0));
    PetscCall(MatShift(A, 1.0));
    PetscCall(KSPSetOperators(ksp, A, A));
    PetscCall(configureSolver(ksp, options));
    PetscCall(VecCopy(E, B));  // B = E: the zeroth bounce is the best cheap guess
    PetscCall(KSPSolve(ksp, E, B));

    KSPConvergedReason reason;
    PetscInt iterations;
    PetscReal emissionNorm, residualNorm;
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCall(KSPGetIterationNumber(ksp, &iterations));
    PetscCall(MatMult(A, B, residual));
    PetscCall(VecAYPX(residual, -1.0, E));
    PetscCall(VecNorm(residual, NORM_2, &residualNorm));
    PetscCall(VecNorm(E, NORM_2, &emissionNorm));
    const double relative = emissionNorm > 0 ? residualNorm / emissionNorm : residualNorm;
    report.iterations += iterations;
    report.residual = std::max(report.residual, relative);
    ++report.channelsSolved;
    if (!std::isfinite(relative)) {
      failure.message = std::string("the ") + channelName +
                        " channel's iterate is not finite (NaN or Inf): nothing was written";
    } else if (reason < 0) {
      failure.message = std::string("the ") + channelName +
                        " channel did not converge: " + KSPConvergedReasons[reason] + " after " +
                        std::to_string(iterations) + " iterations, relative residual " +
                        std::to_string(relative) +
                        (options.solver == "jacobi"
                             ? " (Jacobi needs about 1/(1 - rho) sweeps; try --solver gmres)"
                             : " (raise -ksp_max_it or loosen --rtol)");
    }
    PetscCall(readChannel(B, solution.radiosity, c));
    // Irradiance H = F B: the flux arriving per unit area.
    PetscCall(MatMult(F, B, residual));
    PetscCall(readChannel(residual, solution.irradiance, c));
  }
  report.converged = failure.message.empty();

  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&residual));
  PetscCall(VecDestroy(&rho));
  PetscCall(VecDestroy(&E));
  PetscCall(VecDestroy(&B));
  PetscCall(MatDestroy(&A));
  PetscCall(MatDestroy(&F));
  PetscFunctionReturn(0);
}

}  // namespace

Runtime::Runtime(int argc, char** argv) {
  check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
}

Runtime::~Runtime() { PetscFinalize(); }

ScopedStage::ScopedStage(const char* name) {
  // Stages are registered once per name and pushed again on later uses.
  static std::map<std::string, PetscLogStage> stages;
  auto found = stages.find(name);
  if (found == stages.end()) {
    PetscLogStage stage;
    check(PetscLogStageRegister(name, &stage), "PetscLogStageRegister");
    found = stages.emplace(name, stage).first;
  }
  check(PetscLogStagePush(found->second), "PetscLogStagePush");
}

ScopedStage::~ScopedStage() { PetscLogStagePop(); }

bool hasPetscOption(const char* name) {
  PetscBool found = PETSC_FALSE;
  check(PetscOptionsHasName(nullptr, nullptr, name, &found), "PetscOptionsHasName");
  return found == PETSC_TRUE;
}

LocalSolution solveRadiosity(const formfactor::SparseRows& rows, int64_t globalPatchCount,
                             const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission,
                             const Options& options, Report& report) {
  LocalSolution solution;
  solution.firstPatch = rows.firstRow;
  solution.radiosity.resize(rows.rowCount());
  solution.irradiance.resize(rows.rowCount());
  report = Report{};
  ChannelFailure failure;
  check(solveChannels(rows, globalPatchCount, reflectance, emission, options, solution, report,
                      failure),
        "the solve");
  if (!failure.message.empty()) throw Error(exit_code::kNumerical, failure.message);
  return solution;
}

}  // namespace radiosity::solve
