// The discretisation error of piecewise-constant radiosity, estimated: the solver takes B
// constant over each patch it gathers from, while the light really varies across a patch (most
// near corners, contact lines and shadow edges, where the kernel or the light varies most).
// B = E + ρ H on a patch, and H, unlike B, is continuous across the edges between coplanar
// patches (an emitter's edge, a change of material), so H is reconstructed linearly inside every
// patch about its own mean: its direct part from the patch's own samples of the lights (a shadow
// edge inside the patch shows in their slope), the rest from a least-squares fit to the
// neighbours' means (core/corner_radiosity.h, patchGradients). Gathering ρ times that
// deviation with cosine-weighted rays gives each row's first-order error of H, which the solve
// carries through the bounces (solve::Options::discretisation).
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "formfactor/formfactor.h"
#include "partition/partition.h"

namespace radiosity::solve {

struct DiscretisationReport {
  int64_t rays = 0;
  double seconds = 0;
  /// Per patch j (every patch, on every rank): the error its variation puts into the light the
  /// others gather, Σ_i Σ_c A_i ρ_ic |δH_ij,c| / max(B_ic, floor_c) (δH_ij: the part of row i's
  /// estimated error whose rays hit j; the floor as in measure/light_error.h), in units of
  /// 1 / sourceScale: exact integer sums, the same whichever ranks computed the rows. What an
  /// adaptive refinement round splits by (partition::markLargestErrors). Empty unless asked for.
  std::vector<int64_t> sourceError;
  double sourceScale = 1;
};

/// Rays per patch of the estimate: a quarter of the form factors' samples, within [16, 256].
/// The gathered difference is small and smooth next to B itself, so far fewer rays than the
/// form factors need; but its noise adds to the estimate in quadrature (too few rays inflate
/// it), which matters only once the sampling error is small, i.e. at many samples.
int64_t discretisationRays(int64_t samplesPerPatch);

/// What estimateDiscretisationError works from.
struct DiscretisationInputs {
  const trace::SceneTracer& tracer;
  const Mesh& patches;
  partition::PatchRange owned;  ///< this rank's rows
  uint64_t seed = 0;
  int64_t raysPerPatch = 0;
  int threads = 1;                     ///< the threads that share the rows
  const std::vector<Rgb>& irradiance;  ///< this rank's rows of H
  const std::vector<uint8_t>& hidden;  ///< every patch's flag: sees nothing (empty: none)
  bool attributeSources = false;       ///< fill report.sourceError
};

/// What it finds, for this rank's rows.
struct DiscretisationEstimate {
  std::vector<Rgb> error;     ///< δH_i
  std::vector<Rgb> variance;  ///< of that mean
  DiscretisationReport report;
};

/// For this rank's rows (`owned`): the estimated error of H_i from taking B constant on every
/// patch, δH_i = mean over `raysPerPatch` cosine-weighted rays of ρ_j (H_lin(y) − H̄_lin(j)), j the
/// patch the ray hits, and the variance of that mean. The direct light's slope inside each patch
/// takes a quarter as many shadow rays (at least 16), counted in the report. The rows are shared
/// by `threads` threads. Collective on `comm`; the same on any number of ranks and threads, bit
/// for bit (random numbers keyed by seed, patch and ray; the sums across rows in integers).
/// Patches flagged `hidden` see nothing: their H = 0 is not the lit surface's beside them, so the
/// reconstruction keeps them apart. `attributeSources`: fill report.sourceError (a tenth of the
/// time goes into it), which only a refinement round that may follow reads.
/// `rowsDone`, if given, hears how many of this rank's rows have their rays gathered: 0 when the
/// gathering begins, then after each piece of rows.
DiscretisationEstimate estimateDiscretisationError(
    MPI_Comm comm, const DiscretisationInputs& inputs,
    const std::function<void(int64_t rowsDone)>& rowsDone = {});

}  // namespace radiosity::solve
