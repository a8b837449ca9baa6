// Private to solve/: the sampling error of B, estimated from the run itself, in two steps:
// a model of each row's variance (shape) and its propagation through the system; the caller
// scales the model to the error the estimator really has (Options::calibrate), which Monte
// Carlo formulas cannot know for scrambled Sobol' points. The model has two parts (indirect
// and direct light) that go through the same linear steps: they go together, two vectors a
// product, each pass over F serving both.
#pragma once

#include <petscmat.h>

#include <cstdint>

#include "solve/petsc_handles.h"

namespace radiosity::solve {

/// y = F x for two vectors at once, in one pass over F's entries: PETSc's MAIJ matrix F ⊗ I_2
/// over M's storage (or the single-precision store's components), M = diag(w) F. The two
/// vectors are interleaved patch by patch for it and back.
class PairedProduct {
 public:
  static PetscErrorCode create(Mat M, Vec weight, PairedProduct* product);
  /// Fa = F a, Fb = F b (every vector with the patches' layout). Collective.
  PetscErrorCode apply(Vec a, Vec b, Vec Fa, Vec Fb);
  Mat matrix() const { return M_; }
  Vec weight() const { return weight_; }

 private:
  Mat M_ = nullptr;
  Vec weight_ = nullptr;
  OwnedMat pair_;
  OwnedVec in_, out_;
};

/// A pair of per-patch vectors: the model's indirect and direct parts.
struct VariancePair {
  OwnedVec indirect, direct;
  PetscErrorCode create(Vec like);
};

/// The Monte Carlo variance of row i's estimate of H_i = Σ_j F_ij B_j from N samples, in two
/// parts whose real size the estimators change differently: `indirect`, the light of the
/// patches that do not emit, σ_i² = (Σ_j F_ij x_j² − (Σ_j F_ij x_j)²)/N with x = B where
/// nothing is emitted and 0 on emitters (each hemisphere sample lands on patch j with
/// probability F_ij); `direct`, the same over the emitters only (x = B on emitters). Hemisphere
/// sampling has about their sum; emitter MIS leaves the direct part far smaller; scrambled Sobol'
/// points shrink both, by factors that depend on the scene and N. The caller measures the
/// two scales (Options::calibrate). `emitter` is the 0/1 indicator of the patches that emit.
/// Two paired products.
PetscErrorCode rowVarianceModel(PairedProduct& F, Vec B, Vec emitter, int64_t samples,
                                VariancePair& variance);

/// The variance of each B_i from independent row variances v (of H_i): B_i = E_i + ρ_i H_i
/// carries ρ_i² v_i, plus what the other rows' errors bring through F, bounded by
/// ρ_i² max_j F_ij (F s²)_i (two passes), and the one mode that does not average out, the
/// area-weighted mean, amplified by up to 1/(1 − q): ρ_i² var(mean of δH)/(1 − q)². Linear in
/// v, so the parts of the model are propagated apart (both in each pass) and scaled afterwards.
/// Collective; every vector has the patches' layout. `irradiance`: H's own variance, of which
/// B's is ρ² times (so it is there where ρ = 0 too: a black surface of a thermal run). One
/// product and two paired ones.
PetscErrorCode propagateVariance(PairedProduct& F, Vec rho, Vec area, const VariancePair& variance,
                                 VariancePair& propagated, VariancePair& irradiance);

}  // namespace radiosity::solve
