// The form-factor stage of `radiosity solve`: this rank's rows of F, sampled in pieces with a
// safe point after each piece, reusing the rows a checkpoint already holds.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "core/run_state.h"
#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "run/safe_points.h"

namespace radiosity::run {

/// The rows the stage samples: this rank's rows `owned` of `patches` (traced as `tracer`), by
/// `options`, stored in single precision or not (SplitRows::singlePrecision). Not owned.
struct OwnedRowsJob {
  MPI_Comm comm;
  const trace::SceneTracer& tracer;
  const Mesh& patches;
  partition::PatchRange owned;
  const formfactor::Options& options;
  bool singlePrecision = false;
  bool pairsOnce = false;  ///< exact rows stored once a pair (SplitRows::pairsOnce)
};

/// What the stage calls as it goes. Not owned.
struct SamplingHooks {
  SafePoints& safePoints;
  /// Checkpoints the rows so far, lent: it may move them and must give them back as they were.
  std::function<void(SampledRows&)> save;
  std::function<void(int64_t)> progress;  ///< the rows done so far; empty: none
  double* cpuSeconds = nullptr;           ///< if given, += the process's CPU seconds in sampling
};

/// Samples every row of `job.owned` to options.raysPerPatch samples: rows `saved` already holds
/// with that many are taken as they are, rows with fewer get only the missing samples (the
/// sequence is extensible, so the sums equal a fresh run's bit for bit), the rest are sampled.
/// After each piece (at least 200 per rank, the same number on every rank) the safe point is
/// polled: kSave calls hooks.save with the rows so far (F's store itself, its rows past the cursor
/// empty, where no saved row lies ahead; else a snapshot of the rows done and the saved rows not
/// reached yet, as one tally); kStop calls it and throws solve::SolveStopped. Each rank's rows are
/// cut into the same number of pieces, a piece being the same share of each rank's rows, so that
/// ranks whose blocks were cut by cost (run/rank_balance.h) reach the safe points together.
/// Collective. hooks.cpuSeconds leaves safe points and checkpoints out. The rows come back as F's
/// one store: each piece is turned into values as it is sampled and its tally let go
/// (formfactor::appendRows).
formfactor::SplitRows sampleOwnedRows(const OwnedRowsJob& job, SampledRows saved,
                                      const SamplingHooks& hooks,
                                      formfactor::Statistics& statistics);

}  // namespace radiosity::run
