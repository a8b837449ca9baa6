// The error of B as the solve estimates it: the sampling model scaled and propagated, the
// discretisation error carried through the bounces, and the solver's bound, each in the light
// measure of measure/light_error.h.
#include "solve/solution_error.h"

#include <petscksp.h>

#include <algorithm>
#include <cmath>

#include "formfactor/formfactor.h"
#include "measure/light_error.h"
#include "solve/runtime.h"
#include "solve/sampling_error.h"

namespace radiosity::solve {

namespace {

// δB = ρ δH + ρ F δB carried through every bounce: (I − diag(ρ) F) δB = ρ δH, solved to a
// relative residual of 1e-4 on an operator made of M (no copy). The truncated Neumann sweeps
// this replaces took 50 products where ρ F is not a contraction (a thermal run's re-radiating
// walls) and still fell short where it nearly is not (ρ near 1). BiCGStab, not GMRES: six
// vectors against GMRES's basis of fifteen, where the run's memory peaks (57 MB against 23 MB a
// rank at 10^6 patches), for about as many products (3-7 iterations of two; within 1e-2 of a
// dense solve where ρ = 0.99: tests/solve_bounces_test.cpp). Should it break down, GMRES solves
// again from zero. An iterate short of the tolerance is kept: an error estimate, not B. No
// options reach it: a loose tolerance would report no discretisation error, silently.
struct BounceOperator {
  Mat M;
  Vec weight, rho, work;
};

}  // namespace

PetscErrorCode solveBiCGStabElseGmres(KSP ksp, Vec b, Vec x, PetscReal rtol, bool* fellBack) {
  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPBCGS));
  PetscCall(KSPSetTolerances(ksp, rtol, 0, PETSC_DEFAULT, 200));
  PetscCall(KSPSolve(ksp, b, x));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  const bool breakdown = reason < 0 && reason != KSP_DIVERGED_ITS;
  if (fellBack) *fellBack = breakdown;
  if (breakdown) {  // (its iterate is not kept)
    PetscCall(VecSet(x, 0));
    PetscCall(KSPSetType(ksp, KSPGMRES));
    PetscCall(KSPSolve(ksp, b, x));
  }
  PetscFunctionReturn(0);
}

namespace {

PetscErrorCode bounceMult(Mat A, Vec x, Vec y) {
  BounceOperator* op = nullptr;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &op));
  PetscCall(multiplyF(op->M, op->weight, x, op->work));
  PetscCall(VecPointwiseMult(op->work, op->work, op->rho));
  PetscCall(VecWAXPY(y, -1.0, op->work, x));
  PetscFunctionReturn(0);
}

PetscErrorCode carryThroughBounces(const SharedSystem& s, Vec source, Vec carried) {
  OwnedVec work;
  OwnedMat A;
  OwnedKsp ksp;
  PC pc;
  PetscInt rows, columns, localRows, localColumns;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(s.B, work.out()));
  BounceOperator op{s.M, s.weight, s.rho, work};
  PetscCall(MatGetLocalSize(s.M, &localRows, &localColumns));
  PetscCall(MatGetSize(s.M, &rows, &columns));
  PetscCall(MatCreateShell(PETSC_COMM_WORLD, localRows, localColumns, rows, columns, &op, A.out()));
  PetscCall(MatShellSetOperation(A, MATOP_MULT, reinterpret_cast<void (*)(void)>(bounceMult)));
  PetscCall(KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCNONE));
  PetscCall(solveBiCGStabElseGmres(ksp, source, carried, 1e-4, nullptr));
  PetscFunctionReturn(0);
}

// The discretisation error: each row's error of H (with exact rows, their closed forms' error
// too: formfactor::kExactRowsRelativeError), carried through the bounces
// (carryThroughBounces), then combined per patch with the sampling error in quadrature (its
// own noise taken out).
PetscErrorCode addDiscretisationError(const SolvedScene& scene, LocalSolution& solution,
                                      Report& report) {
  const SharedSystem& s = scene.s;
  const ChannelPlan& plan = scene.plan;
  const std::vector<Rgb>& reflectance = scene.reflectance;
  const std::vector<double>& localArea = scene.localArea;
  const Options& options = scene.options;
  PetscFunctionBeginUser;
  std::vector<Rgb> errorH, varianceH;
  options.discretisation(solution.irradiance, errorH, varianceH);
  if (options.exactRows) {  // (and the closed forms' own, in magnitude: the sign is the mesh's)
    for (size_t r = 0; r < errorH.size(); ++r) {
      for (int k = 0; k < 3; ++k) {
        const double closedForms = formfactor::kExactRowsRelativeError * solution.irradiance[r][k];
        errorH[r][k] = std::copysign(std::hypot(errorH[r][k], closedForms), errorH[r][k]);
      }
    }
  }
  ScopedStage stage("Discretisation bounces");
  solution.radiosityDiscretisation.assign(solution.radiosity.size(), Rgb{0, 0, 0});
  solution.irradianceDiscretisation.assign(solution.radiosity.size(), Rgb{0, 0, 0});
  OwnedVec local, swept;
  for (OwnedVec* v : {&local, &swept}) PetscCall(VecDuplicate(s.B, v->out()));
  for (int c = 0; c < 3; ++c) {
    if (plan.noReflection[c]) continue;
    if (plan.sameAs[c] >= 0) {  // the same ρ, E and so H: the same errors (grey and thermal runs)
      copyChannel(solution.radiosityDiscretisation, plan.sameAs[c], c);
      copyChannel(solution.irradianceDiscretisation, plan.sameAs[c], c);
      continue;
    }
    PetscCall(fillChannel(s.rho, reflectance, c));
    PetscCall(fillChannel(local, errorH, c));
    PetscCall(VecPointwiseMult(local, local, s.rho));
    PetscCall(carryThroughBounces(s, local, swept));
    PetscCall(readChannel(swept, solution.radiosityDiscretisation, c));
    // H's: the row's own error and what the others' δB bring, δH = δH_row + F δB (so that it
    // is there where ρ = 0 too; where ρ > 0 it is δB / ρ).
    PetscCall(multiplyF(s.M, s.weight, swept, local));
    PetscCall(readChannel(local, solution.irradianceDiscretisation, c));
    for (size_t r = 0; r < errorH.size(); ++r)
      solution.irradianceDiscretisation[r][c] += errorH[r][c];
  }
  for (OwnedVec* v : {&local, &swept}) v->reset();
  // (one more array, not three: this is the run's peak where the bounces' Krylov basis is not)
  std::vector<Rgb>().swap(errorH);
  std::vector<Rgb> total(solution.radiosity.size());
  for (size_t r = 0; r < solution.radiosity.size(); ++r) {
    for (int k = 0; k < 3; ++k) {
      const double rho = reflectance[r][k], d = solution.radiosityDiscretisation[r][k];
      const double squared = std::max(0.0, d * d - rho * rho * varianceH[r][k]);
      // (stored with its noise taken out, signed: the estimated true B minus B)
      solution.radiosityDiscretisation[r][k] = std::copysign(std::sqrt(squared), d);
      total[r][k] = std::sqrt(squared + std::pow(solution.radiosityStderr[r][k], 2));
      // H's, its estimate's noise taken out as B's (the same noise before ρ).
      double& h = solution.irradianceDiscretisation[r][k];
      h = std::copysign(std::sqrt(std::max(0.0, h * h - varianceH[r][k])), h);
    }
  }
  report.discretisationErrorB =
      relativeLightError(PETSC_COMM_WORLD, localArea, reflectance, solution.radiosity,
                         solution.radiosityDiscretisation);
  report.errorB =
      relativeLightError(PETSC_COMM_WORLD, localArea, reflectance, solution.radiosity, total);
  for (size_t r = 0; r < total.size(); ++r) {  // H's total: B's over ρ (B = E + ρ H)
    for (int k = 0; k < 3; ++k)
      total[r][k] = reflectance[r][k] > 0 ? total[r][k] / reflectance[r][k] : 0.0;
  }
  report.errorH =
      relativeLightError(PETSC_COMM_WORLD, localArea, reflectance, solution.irradiance, total);
  report.discretisationShare =
      *std::max_element(report.discretisationErrorB.begin(), report.discretisationErrorB.end());
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode modelChannelVariance(const SharedSystem& s, const std::vector<Rgb>& reflectance,
                                    int c, int64_t samples, VarianceModel& model) {
  PairedProduct F;
  VariancePair variance, propagated, irradiance;
  PetscFunctionBeginUser;
  PetscCall(PairedProduct::create(s.M, s.weight, &F));
  for (VariancePair* pair : {&variance, &propagated, &irradiance}) PetscCall(pair->create(s.B));
  PetscCall(fillChannel(s.rho, reflectance, c));
  PetscCall(rowVarianceModel(F, s.B, s.emitter, samples, variance));
  PetscCall(propagateVariance(F, s.rho, s.area, variance, propagated, irradiance));
  PetscCall(readChannel(propagated.indirect, model.indirectB, c));
  PetscCall(readChannel(irradiance.indirect, model.indirectH, c));
  PetscCall(readChannel(propagated.direct, model.directB, c));
  PetscCall(readChannel(irradiance.direct, model.directH, c));
  PetscFunctionReturn(0);
}

PetscErrorCode estimateSolutionError(const SolvedScene& scene, VarianceModel model,
                                     LocalSolution& solution, Report& report) {
  const std::vector<Rgb>& reflectance = scene.reflectance;
  const std::vector<double>& localArea = scene.localArea;
  const Options& options = scene.options;
  PetscFunctionBeginUser;
  if (options.calibrate && !options.exactRows)
    report.calibration = options.calibrate(solution.radiosity);
  std::vector<Rgb>& irradianceStderr = solution.irradianceStderr;
  irradianceStderr.assign(solution.radiosity.size(), Rgb{0, 0, 0});
  for (size_t r = 0; r < solution.radiosity.size(); ++r) {
    for (int k = 0; k < 3; ++k) {
      const double error = std::sqrt(report.calibration.indirect[k] * model.indirectB[r][k] +
                                     report.calibration.direct[k] * model.directB[r][k]);
      solution.radiosityStderr[r][k] = std::isfinite(error) ? error : 0.0;
      // H's own: B's over ρ where ρ > 0 (B = E + ρ H), and there on black patches too.
      const double errorH = std::sqrt(report.calibration.indirect[k] * model.indirectH[r][k] +
                                      report.calibration.direct[k] * model.directH[r][k]);
      irradianceStderr[r][k] = std::isfinite(errorH) ? errorH : 0.0;
      // H exactly 0: no sample of the row met light (the ground around a closed room). The
      // mean mode of the others' errors does not reach it: it has no error to give.
      if (solution.irradiance[r][k] == 0)
        solution.radiosityStderr[r][k] = irradianceStderr[r][k] = 0;
    }
  }
  report.samplingErrorB = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                             solution.radiosity, solution.radiosityStderr);
  report.samplingErrorH = relativeLightError(PETSC_COMM_WORLD, localArea, reflectance,
                                             solution.irradiance, irradianceStderr);
  report.samplingShare =
      *std::max_element(report.samplingErrorB.begin(), report.samplingErrorB.end());
  report.errorB = report.samplingErrorB;
  report.errorH = report.samplingErrorH;
  model = VarianceModel();  // (used up: its four arrays would sit under the bounces' peak)

  if (options.discretisation) {
    PetscCall(addDiscretisationError(scene, solution, report));
  }
  report.relativeStderr = *std::max_element(report.errorB.begin(), report.errorB.end());
  PetscFunctionReturn(0);
}

std::array<double, 3> solverErrors(const std::array<ChannelResult, 3>& results,
                                   const std::vector<double>& area,
                                   const std::vector<Rgb>& reflectance,
                                   const LocalSolution& solution) {
  const Rgb bound{results[0].absoluteBound, results[1].absoluteBound, results[2].absoluteBound};
  const std::vector<Rgb> errors(solution.radiosity.size(), bound);
  return relativeLightError(PETSC_COMM_WORLD, area, reflectance, solution.radiosity, errors);
}

}  // namespace radiosity::solve
