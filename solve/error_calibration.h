// The scale of the sampling-error model, measured: the Monte Carlo variance formulas of
// solve/sampling_error.h give the shape of the error over the patches, but scrambled Sobol'
// points converge faster than Monte Carlo by a factor that depends on the scene, the estimator
// and N, and MIS leaves a direct-light error the formula does not see. So, after the solve,
// a random subset of patches is gathered again with the same estimator and N samples under
// independent scrambles: the spread of those replicates, with B fixed, is the true variance of
// those rows' estimates of H. The model has two parts (indirect and direct light) that the
// estimators and the Sobol' points shrink differently: their mix is the one under which the
// measured variances are most likely (each a scaled χ² with replicates − 1 degrees of
// freedom), and the overall scale makes the weighted sum match as the headline figure weighs
// the patches. The model a replicate's spread is compared with is the model evaluated on the
// replicates' own rows (their mean), not on the solve's row: a rare event (a ray lost at an
// edge of a closed box) then enters both or neither. Both are summed without cancellation.
// Costs about 1/16 of the form-factor stage's rays, no stored rows.
#pragma once

#include <mpi.h>

#include <array>
#include <vector>

#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

struct CalibrationReport {
  solve::VarianceScale scale;  ///< per channel, what each part of the model is multiplied by
  int64_t patches = 0;         ///< patches gathered again
  int replicates = 0;          ///< independent gathers of each
  int64_t rays = 0;
  double seconds = 0;
};

/// Measures the scales per channel (collective on `comm`; the same on any number of ranks).
/// `radiosity` holds this rank's rows (`owned`) of B; `sampling` the options the rows of F were
/// sampled with (estimator, samples per row, seed).
CalibrationReport calibrateSamplingError(MPI_Comm comm, const trace::SceneTracer& tracer,
                                         const Mesh& patches, partition::PatchRange owned,
                                         const formfactor::Options& sampling,
                                         const std::vector<Rgb>& radiosity);

/// The patches [owned) of B and other per-row triples for any global ids, fetched from the
/// ranks that own them (collective; `ids` any order, repeats allowed). `owned` is this rank's
/// block; the blocks, in rank order, may be cut any way (by count or by cost).
std::vector<Rgb> fetchRows(MPI_Comm comm, int64_t patchCount, partition::PatchRange owned,
                           const std::vector<Rgb>& local, const std::vector<int64_t>& ids);

}  // namespace radiosity::solve
