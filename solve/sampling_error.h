// Private to solve/: the sampling error of B, estimated from the run itself, in two steps:
// a model of each row's variance (shape) and its propagation through the system; the caller
// scales the model to the error the estimator really has (Options::calibrate), which Monte
// Carlo formulas cannot know for scrambled Sobol' points.
#pragma once

#include <petscmat.h>

#include <cstdint>

namespace radiosity::solve {

/// The Monte Carlo variance of row i's estimate of H_i = Σ_j F_ij B_j from N samples, in two
/// parts whose real size the estimators change differently: `indirect`, the light of the
/// patches that do not emit, σ_i² = (Σ_j F_ij x_j² − (Σ_j F_ij x_j)²)/N with x = B where
/// nothing is emitted and 0 on emitters (each hemisphere sample lands on patch j with
/// probability F_ij); `direct`, the same over the emitters only (x = B on emitters). Hemisphere
/// sampling has about their sum; emitter MIS leaves the direct part far smaller; scrambled Sobol'
/// points shrink both, by factors that depend on the scene and N. The caller measures the
/// two scales (Options::calibrate). `emitter` is the 0/1 indicator of the patches that emit.
/// M = diag(w) F. Four products with F.
PetscErrorCode rowVarianceModel(Mat M, Vec weight, Vec B, Vec emitter, int64_t samples,
                                Vec indirect, Vec direct);

/// The variance of each B_i from independent row variances v (of H_i): B_i = E_i + ρ_i H_i
/// carries ρ_i² v_i, plus what the other rows' errors bring through F, bounded by
/// ρ_i² max_j F_ij (F s²)_i (two passes), and the one mode that does not average out, the
/// area-weighted mean, amplified by up to 1/(1 − q): ρ_i² var(mean of δH)/(1 − q)². Linear in
/// v, so the parts of the model can be propagated apart and scaled afterwards. Collective;
/// every vector has the patches' layout. `irradiance`: H_i's own variance, of which B_i's is
/// ρ_i² times (so it is there where ρ_i = 0 too: a black surface of a thermal run).
PetscErrorCode propagateVariance(Mat M, Vec weight, Vec rho, Vec area, Vec variance, Vec propagated,
                                 Vec irradiance);

}  // namespace radiosity::solve
