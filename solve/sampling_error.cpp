// The variance model of each row and its propagation into B (see sampling_error.h).
#include "solve/sampling_error.h"

#include <cmath>

#include "solve/petsc_handles.h"
#include "solve/shared_system.h"

namespace radiosity::solve {

namespace {

// (Σ_j F_ij x_j² − (Σ_j F_ij x_j)²)/N, x = B ⊙ mask, clipped at 0 (round-off).
PetscErrorCode partVariance(Mat M, Vec weight, Vec B, Vec mask, int64_t samples, Vec variance) {
  OwnedVec x, squared, mean;
  PetscFunctionBeginUser;
  for (OwnedVec* v : {&x, &squared, &mean}) PetscCall(VecDuplicate(B, v->out()));
  PetscCall(VecPointwiseMult(x, B, mask));
  PetscCall(multiplyF(M, weight, x, mean));
  PetscCall(VecPointwiseMult(squared, x, x));
  PetscCall(multiplyF(M, weight, squared, variance));
  PetscCall(VecPointwiseMult(squared, mean, mean));
  PetscCall(VecAXPY(variance, -1.0, squared));
  PetscCall(VecScale(variance, 1.0 / static_cast<PetscReal>(samples)));
  PetscCall(VecSet(squared, 0.0));
  PetscCall(VecPointwiseMax(variance, variance, squared));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode rowVarianceModel(Mat M, Vec weight, Vec B, Vec emitter, int64_t samples,
                                Vec indirect, Vec direct) {
  OwnedVec other;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(emitter, other.out()));
  PetscCall(VecSet(other, 1.0));
  PetscCall(VecAXPY(other, -1.0, emitter));
  PetscCall(partVariance(M, weight, B, other, samples, indirect));
  PetscCall(partVariance(M, weight, B, emitter, samples, direct));
  PetscFunctionReturn(0);
}

PetscErrorCode propagateVariance(Mat M, Vec weight, Vec rho, Vec area, Vec variance, Vec result,
                                 Vec irradiance) {
  OwnedVec local, work, rowMax, propagated, rho2, ones;
  PetscFunctionBeginUser;
  for (OwnedVec* v : {&local, &work, &rowMax, &propagated, &rho2, &ones})
    PetscCall(VecDuplicate(variance, v->out()));

  // The mean mode: var(Σ A_i δH_i / Σ A_i) = Σ A_i² σ_i² / (Σ A_i)².
  PetscReal totalArea, meanVariance;
  PetscCall(VecSum(area, &totalArea));
  PetscCall(VecPointwiseMult(work, area, area));
  PetscCall(VecDot(work, variance, &meanVariance));
  meanVariance /= totalArea * totalArea;
  // q = max_i ρ_i Σ_j F_ij.
  PetscReal q;
  PetscCall(VecSet(ones, 1.0));
  PetscCall(multiplyF(M, weight, ones, work));
  PetscCall(VecPointwiseMult(work, work, rho));
  PetscCall(VecMax(work, nullptr, &q));

  // s² = ρ² σ², then s² ← ρ² σ² + ρ² max_j F_ij (F s²) twice.
  PetscCall(VecPointwiseMult(rho2, rho, rho));
  PetscCall(VecPointwiseMult(local, variance, rho2));
  PetscCall(MatGetRowMaxAbs(M, rowMax, nullptr));
  PetscCall(VecPointwiseDivide(rowMax, rowMax, weight));
  PetscCall(VecCopy(local, result));
  for (int pass = 0; pass < 2; ++pass) {
    PetscCall(multiplyF(M, weight, result, propagated));
    PetscCall(VecPointwiseMult(propagated, propagated, rowMax));
    // (H's variance before ρ²: the row's own, and what the others' B bring)
    if (pass == 1) PetscCall(VecWAXPY(irradiance, 1.0, variance, propagated));
    PetscCall(VecPointwiseMult(propagated, propagated, rho2));
    PetscCall(VecWAXPY(result, 1.0, local, propagated));
  }
  if (q < 1) {
    PetscCall(VecAXPY(result, meanVariance / ((1 - q) * (1 - q)), rho2));
    PetscCall(VecShift(irradiance, meanVariance / ((1 - q) * (1 - q))));
  }
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
