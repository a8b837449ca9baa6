// The variance model of each row and its propagation into B (see sampling_error.h).
#include "solve/sampling_error.h"

#include <cmath>
#include <utility>

#include "solve/shared_system.h"
#include "solve/single_precision_matrix.h"

namespace radiosity::solve {

PetscErrorCode PairedProduct::create(Mat M, Vec weight, PairedProduct* product) {
  PetscFunctionBeginUser;
  product->M_ = M;
  product->weight_ = weight;
  if (isSinglePrecisionMatrix(M)) {
    PetscCall(createSinglePrecisionComponents(M, 2, product->pair_.out()));
  } else {
    PetscCall(MatCreateMAIJ(M, 2, product->pair_.out()));  // shares M's values and indices
  }
  PetscCall(MatCreateVecs(product->pair_, product->in_.out(), product->out_.out()));
  PetscCall(VecSetBlockSize(product->in_, 2));
  PetscCall(VecSetBlockSize(product->out_, 2));
  PetscFunctionReturn(0);
}

PetscErrorCode PairedProduct::apply(Vec a, Vec b, Vec Fa, Vec Fb) {
  PetscFunctionBeginUser;
  PetscCall(VecStrideScatter(a, 0, in_, INSERT_VALUES));
  PetscCall(VecStrideScatter(b, 1, in_, INSERT_VALUES));
  PetscCall(MatMult(pair_, in_, out_));
  PetscCall(VecStrideGather(out_, 0, Fa, INSERT_VALUES));
  PetscCall(VecStrideGather(out_, 1, Fb, INSERT_VALUES));
  PetscCall(VecPointwiseDivide(Fa, Fa, weight_));
  PetscCall(VecPointwiseDivide(Fb, Fb, weight_));
  PetscFunctionReturn(0);
}

PetscErrorCode VariancePair::create(Vec like) {
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(like, indirect.out()));
  PetscCall(VecDuplicate(like, direct.out()));
  PetscFunctionReturn(0);
}

PetscErrorCode rowVarianceModel(PairedProduct& F, Vec B, Vec emitter, int64_t samples,
                                VariancePair& variance) {
  VariancePair x, squared, mean;
  PetscFunctionBeginUser;
  for (VariancePair* pair : {&x, &squared, &mean}) PetscCall(pair->create(B));
  // x = B ⊙ mask: the patches that do not emit (indirect), those that do (direct).
  PetscCall(VecSet(x.indirect, 1.0));
  PetscCall(VecAXPY(x.indirect, -1.0, emitter));
  PetscCall(VecPointwiseMult(x.indirect, x.indirect, B));
  PetscCall(VecPointwiseMult(x.direct, emitter, B));
  PetscCall(F.apply(x.indirect, x.direct, mean.indirect, mean.direct));
  PetscCall(VecPointwiseMult(squared.indirect, x.indirect, x.indirect));
  PetscCall(VecPointwiseMult(squared.direct, x.direct, x.direct));
  PetscCall(F.apply(squared.indirect, squared.direct, variance.indirect, variance.direct));
  // (Σ_j F_ij x_j² − (Σ_j F_ij x_j)²)/N, clipped at 0 (round-off).
  for (auto [part, average] : {std::pair{variance.indirect.get(), mean.indirect.get()},
                               std::pair{variance.direct.get(), mean.direct.get()}}) {
    PetscCall(VecPointwiseMult(average, average, average));
    PetscCall(VecAXPY(part, -1.0, average));
    PetscCall(VecScale(part, 1.0 / static_cast<PetscReal>(samples)));
    PetscCall(VecSet(average, 0.0));
    PetscCall(VecPointwiseMax(part, part, average));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode propagateVariance(PairedProduct& F, Vec rho, Vec area, const VariancePair& variance,
                                 VariancePair& result, VariancePair& irradiance) {
  OwnedVec work, rowMax, rho2, ones;
  VariancePair local, propagated;
  PetscFunctionBeginUser;
  for (OwnedVec* v : {&work, &rowMax, &rho2, &ones}) PetscCall(VecDuplicate(rho, v->out()));
  for (VariancePair* pair : {&local, &propagated}) PetscCall(pair->create(rho));

  // q = max_i ρ_i Σ_j F_ij.
  PetscReal q;
  PetscCall(VecSet(ones, 1.0));
  PetscCall(multiplyF(F.matrix(), F.weight(), ones, work));
  PetscCall(VecPointwiseMult(work, work, rho));
  PetscCall(VecMax(work, nullptr, &q));

  // s² = ρ² σ², then s² ← ρ² σ² + ρ² max_j F_ij (F s²) twice.
  PetscCall(VecPointwiseMult(rho2, rho, rho));
  PetscCall(MatGetRowMaxAbs(F.matrix(), rowMax, nullptr));
  PetscCall(VecPointwiseDivide(rowMax, rowMax, F.weight()));
  const std::pair<Vec, Vec> parts[] = {{variance.indirect, local.indirect},
                                       {variance.direct, local.direct}};
  for (auto [own, scaled] : parts) PetscCall(VecPointwiseMult(scaled, own, rho2));
  PetscCall(VecCopy(local.indirect, result.indirect));
  PetscCall(VecCopy(local.direct, result.direct));
  for (int pass = 0; pass < 2; ++pass) {
    PetscCall(F.apply(result.indirect, result.direct, propagated.indirect, propagated.direct));
    const Vec in[] = {propagated.indirect, propagated.direct};
    const Vec own[] = {variance.indirect, variance.direct};
    const Vec scaled[] = {local.indirect, local.direct};
    const Vec out[] = {result.indirect, result.direct};
    const Vec ownH[] = {irradiance.indirect, irradiance.direct};
    for (int k = 0; k < 2; ++k) {
      PetscCall(VecPointwiseMult(in[k], in[k], rowMax));
      // (H's variance before ρ²: the row's own, and what the others' B bring)
      if (pass == 1) PetscCall(VecWAXPY(ownH[k], 1.0, own[k], in[k]));
      PetscCall(VecPointwiseMult(in[k], in[k], rho2));
      PetscCall(VecWAXPY(out[k], 1.0, scaled[k], in[k]));
    }
  }
  if (q < 1) {
    // The mean mode: var(Σ A_i δH_i / Σ A_i) = Σ A_i² σ_i² / (Σ A_i)².
    PetscReal totalArea;
    PetscCall(VecSum(area, &totalArea));
    PetscCall(VecPointwiseMult(work, area, area));
    const Vec own[] = {variance.indirect, variance.direct};
    const Vec out[] = {result.indirect, result.direct};
    const Vec ownH[] = {irradiance.indirect, irradiance.direct};
    for (int k = 0; k < 2; ++k) {
      PetscReal meanVariance;
      PetscCall(VecDot(work, own[k], &meanVariance));
      meanVariance /= totalArea * totalArea;
      PetscCall(VecAXPY(out[k], meanVariance / ((1 - q) * (1 - q)), rho2));
      PetscCall(VecShift(ownH[k], meanVariance / ((1 - q) * (1 - q))));
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
