// Private to solve/: the sampling error of B, estimated from the run itself.
#pragma once

#include <petscmat.h>

#include <cstdint>

namespace radiosity::solve {

/// Standard error of each B_i, from the variance of the estimator of H_i = Σ_j F_ij B_j: a
/// row's N samples each land on one patch j with probability F_ij, so H_i's estimate has
/// variance σ_i² = (Σ_j F_ij B_j² − H_i²)/N (Monte Carlo; scrambled Sobol' points do better, so
/// the estimate errs on the safe side). B_i = E_i + ρ_i H_i carries ρ_i² σ_i², plus what the
/// other rows' errors bring through F: bounded by ρ_i² max_j F_ij (F v)_i (two passes), and the
/// one mode that does not average out, the mean, amplified by up to 1/(1 − q):
/// ρ_i² var(mean of δH)/(1 − q)². M = diag(w) F; every vector has the patches' layout.
/// Returns in `standardError`; the area-weighted relative RMS in `relative`. Collective.
PetscErrorCode samplingError(Mat M, Vec weight, Vec rho, Vec B, Vec H, Vec area, int64_t samples,
                             Vec standardError, PetscReal* relative);

}  // namespace radiosity::solve
