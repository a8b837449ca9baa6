// Private to solve/: the estimated error of B, per patch and per channel: the sampling error
// (the variance model of sampling_error.h, scaled to the estimator's real error), the
// discretisation error carried through the bounces, and the solver's own error bound.
#pragma once

#include <petscksp.h>
#include <petscmat.h>

#include <array>
#include <cstdint>
#include <vector>

#include "solve/channel_plan.h"
#include "solve/channel_solve.h"
#include "solve/shared_system.h"

namespace radiosity::solve {

/// The variance model of every channel (sampling_error.h): each row's variance of H in two
/// parts (indirect, direct), each propagated to B; only the propagated parts are kept.
struct VarianceModel {
  std::vector<Rgb> indirectB, directB;
  std::vector<Rgb> indirectH, directH;  ///< H's own (B's over ρ², and where ρ = 0)
  void resize(size_t rows) {
    for (auto* v : {&indirectB, &directB, &indirectH, &directH}) v->assign(rows, Rgb{0, 0, 0});
  }
  void copyChannel(int from, int to) {
    for (auto* v : {&indirectB, &directB, &indirectH, &directH})
      if (!v->empty()) solve::copyChannel(*v, from, to);
  }
};

/// The model's variances of channel c, from its B in s.B and `samples` per row.
PetscErrorCode modelChannelVariance(const SharedSystem& s, const std::vector<Rgb>& reflectance,
                                    int c, int64_t samples, VarianceModel& model);

/// What the error of B is estimated on, besides the variance model: the solved system, the
/// plan, this rank's rows' ρ and areas, and the options.
struct SolvedScene {
  const SharedSystem& s;
  const ChannelPlan& plan;
  const std::vector<Rgb>& reflectance;
  const std::vector<double>& localArea;
  const Options& options;
};

/// The sampling error of B and H (and with Options::discretisation, the discretisation error
/// and both combined), per patch into the solution and per channel into the report, once every
/// channel is solved. Takes the model (moved in) to free it before the discretisation estimate,
/// where the run's memory peaks.
PetscErrorCode estimateSolutionError(const SolvedScene& scene, VarianceModel model,
                                     LocalSolution& solution, Report& report);

/// Solves b = A x with `ksp` (its operators and preconditioner set) by BiCGStab to the relative
/// residual `rtol` (at most 200 iterations; an iterate short of it is kept); should BiCGStab
/// break down, its iterate is dropped and GMRES solves again from zero (`fellBack` says so
/// when given). The bounces' solve: BiCGStab's six vectors against GMRES's basis where the
/// run's memory peaks.
PetscErrorCode solveBiCGStabElseGmres(KSP ksp, Vec b, Vec x, PetscReal rtol, bool* fellBack);

/// The solver's error bound of each channel in the light measure (measure/light_error.h).
std::array<double, 3> solverErrors(const std::array<ChannelResult, 3>& results,
                                   const std::vector<double>& area,
                                   const std::vector<Rgb>& reflectance,
                                   const LocalSolution& solution);

}  // namespace radiosity::solve
