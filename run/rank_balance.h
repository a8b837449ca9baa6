// Which rows each rank samples and solves: contiguous blocks along the patch curve, cut where
// the work is even rather than where the counts are (--balance cost, the default). A short pilot
// measures the work. Where the blocks are cut changes who computes a row, never the row, so the
// answer is the same for any cut (docs/design/meshing.md, "Balancing the ranks").
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "run/balance_mode.h"

namespace radiosity::run {

/// Where --balance auto starts to cut by cost: on fewer ranks the split by count is close to even
/// and the pilot costs about what the cut by cost saves, or more (measured in docs/scaling.md,
/// "Balancing the ranks").
inline constexpr int kCostBalancedRanks = 4;

/// The pilot's shape, fixed so that it is the same for any number of threads.
inline constexpr int64_t kPilotSamples = 16;  ///< samples of each pilot row (thrown away)
/// At most this share of the form-factor stage's samples goes to the pilot (one patch in
/// `stride` is sampled); its time against the stage's is in docs/scaling.md.
inline constexpr double kPilotShare = 0.01;
inline constexpr int64_t kStretchesPerRank = 64;  ///< runs of the curve costed apart
/// A nonzero's cost in the solve, in samples of the form-factor stage: the time of the products
/// with F a solve makes (3 channels) over the time of a sample, both measured (docs/scaling.md).
inline constexpr double kNonzeroInSamples = 0.25;
/// Below this many samples in all (patches × rays) the stage is too short to be worth a pilot.
inline constexpr double kSmallestBalancedStage = 1 << 18;

/// The blocks and how they were found, for the log.
struct Balance {
  partition::Blocks blocks = partition::Blocks::byCount(0, 1);
  bool byCost = false;
  std::string why;              ///< why by count, when it is
  double pilotSeconds = 0;      ///< wall time of the pilot, the slowest rank's
  double pilotShare = 0;        ///< its samples over the stage's
  double predicted = 1;         ///< max/mean of the modelled cost per rank under `blocks`
  double predictedByCount = 1;  ///< the same under blocks by count
};

/// Cost per patch along the curve, modelled from the pilot: the patches
/// [runStart[s], runStart[s + 1]) each cost perPatch[s] (CPU seconds).
struct CostModel {
  std::vector<int64_t> runStart;
  std::vector<double> perPatch;
  /// max/mean of the modelled cost of the blocks.
  double imbalance(const partition::Blocks& blocks) const;
};

/// The pilot, collective: the curve is cut into kStretchesPerRank × ranks runs, each measured by
/// one rank (rank r takes runs r, r + ranks, … in a scrambled order, so that a change of the
/// machine's load over time does not tilt the curve). In a run, every `stride`-th patch gets a
/// row with `options`' estimator (another seed: the rows are thrown away) twice, with
/// kPilotSamples/4 and then 3·kPilotSamples/4 samples, each timed by the thread's CPU clock
/// (right when ranks share cores): the difference is the cost of half the samples without what
/// a row costs whatever its samples, which is estimated once for the whole curve. A patch costs
///   that fixed part + raysPerPatch × (CPU seconds per sample in its run)   form factors
///   + kNonzeroInSamples × (mean seconds per sample) × nonzeros               the solve
/// with its row's nonzeros at raysPerPatch samples estimated from the pilot row (each pilot hit
/// j stands for the chance 1 − (1 − p_j)^N that N samples find j, p_j from the geometry).
CostModel measureCosts(MPI_Comm comm, const trace::SceneTracer& tracer, const Mesh& patches,
                       const formfactor::Options& options, double* pilotShare = nullptr);

/// The blocks of `patches` (traced as `tracer`) for the form factors of `options`, by cost or by
/// count: by count with one rank, a tiny stage (under kSmallestBalancedStage samples) or fewer
/// patches than runs. The same on every rank. Collective.
Balance balanceRows(MPI_Comm comm, const trace::SceneTracer& tracer, const Mesh& patches,
                    const formfactor::Options& options, BalanceMode mode);

/// The log line of the split: "balance: blocks by measured cost; pilot T s (P % of the stage's
/// samples); predicted max/mean M (by count C)".
std::string describeBalance(const Balance& balance);

/// The log line of what the split gave, from every rank's CPU seconds in the form-factor stage and
/// its nonzeros: "balance: form-factor CPU time per rank max/mean 1.03 ..." Collective.
std::string describeOutcome(MPI_Comm comm, double cpuSeconds, int64_t nonzeros);

/// CPU seconds of the calling thread, and of the whole process (every thread).
double threadCpuSeconds();
double processCpuSeconds();

}  // namespace radiosity::run
