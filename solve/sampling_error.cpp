#include "solve/sampling_error.h"

#include <cmath>

namespace radiosity::solve {

namespace {

// y = F x = diag(1/w) M x.
PetscErrorCode multiplyF(Mat M, Vec weight, Vec x, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(MatMult(M, x, y));
  PetscCall(VecPointwiseDivide(y, y, weight));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode samplingError(Mat M, Vec weight, Vec rho, Vec B, Vec H, Vec area, int64_t samples,
                             Vec standardError, PetscReal* relative) {
  Vec variance, squared, rowMax, propagated, rho2, ones;
  PetscFunctionBeginUser;
  for (Vec* v : {&variance, &squared, &rowMax, &propagated, &rho2, &ones})
    PetscCall(VecDuplicate(B, v));
  // σ² = (F B² − H²)/N, clipped at 0 (round-off).
  PetscCall(VecPointwiseMult(squared, B, B));
  PetscCall(multiplyF(M, weight, squared, variance));
  PetscCall(VecPointwiseMult(squared, H, H));
  PetscCall(VecAXPY(variance, -1.0, squared));
  PetscCall(VecScale(variance, 1.0 / static_cast<PetscReal>(samples)));
  PetscCall(VecSet(squared, 0.0));
  PetscCall(VecPointwiseMax(variance, variance, squared));

  // The mean mode: var(Σ A_i δH_i / Σ A_i) = Σ A_i² σ_i² / (Σ A_i)².
  PetscReal totalArea, meanVariance;
  PetscCall(VecSum(area, &totalArea));
  PetscCall(VecPointwiseMult(squared, area, area));
  PetscCall(VecDot(squared, variance, &meanVariance));
  meanVariance /= totalArea * totalArea;
  // q = max_i ρ_i Σ_j F_ij.
  PetscReal q;
  PetscCall(VecSet(ones, 1.0));
  PetscCall(multiplyF(M, weight, ones, squared));
  PetscCall(VecPointwiseMult(squared, squared, rho));
  PetscCall(VecMax(squared, nullptr, &q));

  // v = ρ² σ², then v ← ρ² σ² + ρ² max_j F_ij (F v) twice.
  PetscCall(VecPointwiseMult(rho2, rho, rho));
  PetscCall(VecPointwiseMult(variance, variance, rho2));  // now ρ² σ²
  PetscCall(MatGetRowMaxAbs(M, rowMax, nullptr));
  PetscCall(VecPointwiseDivide(rowMax, rowMax, weight));
  PetscCall(VecCopy(variance, standardError));
  for (int pass = 0; pass < 2; ++pass) {
    PetscCall(multiplyF(M, weight, standardError, propagated));
    PetscCall(VecPointwiseMult(propagated, propagated, rowMax));
    PetscCall(VecPointwiseMult(propagated, propagated, rho2));
    PetscCall(VecWAXPY(standardError, 1.0, variance, propagated));
  }
  if (q < 1) PetscCall(VecAXPY(standardError, meanVariance / ((1 - q) * (1 - q)), rho2));
  PetscCall(VecSqrtAbs(standardError));

  // Relative: ‖A^½ stderr‖ / ‖A^½ B‖.
  PetscReal errorSquares, valueSquares;
  PetscCall(VecPointwiseMult(squared, standardError, standardError));
  PetscCall(VecDot(squared, area, &errorSquares));
  PetscCall(VecPointwiseMult(squared, B, B));
  PetscCall(VecDot(squared, area, &valueSquares));
  *relative = valueSquares > 0 ? std::sqrt(errorSquares / valueSquares) : 0;
  for (Vec* v : {&variance, &squared, &rowMax, &propagated, &rho2, &ones}) PetscCall(VecDestroy(v));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
