// formfactor: the rows F_i· of the form-factor matrix, by Monte Carlo ray casting through
// trace/'s scene tracer or by closed forms where the scene allows.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "formfactor/estimator.h"
#include "trace/trace.h"

namespace radiosity::formfactor {

using trace::SceneTracer;

/// How emitter MIS picks the light of each sample (formfactor/light_choice.h), in words: part
/// of a checkpoint's identity, so that sums drawn one way are never extended another way.
std::string misLightChoice();

/// The estimator a scene should use when the user names none, and why.
struct EstimatorChoice {
  Estimator estimator = Estimator::kHemisphere;
  std::string reason;
};

/// Emitter MIS unless nearly every patch emits (kMisEmitterShare of the area or more, as in
/// thermal radiation, where hemisphere rays find emitters as well as area sampling does, at one
/// ray per sample instead of two) or nothing does. MIS is the more accurate per second both
/// where the light is a small share of the area and where it is half of it (docs/accuracy.md).
EstimatorChoice chooseEstimator(const Mesh& patches);
inline constexpr double kMisEmitterShare = 0.9;

/// Whether the rows can be had without rays, and why (or why not).
struct RowsChoice {
  bool exact = false;
  std::string reason;
};

/// Exact rows (Options::exactRows) where every pair of patches that face each other sees each
/// other whole, which holds when every vertex lies on or in front of every patch's plane (a
/// convex enclosure, open or closed: a room without furniture, a furnace, the cube of the view
/// factor benchmarks), and N ≤ kExactPatchesPerRay × rays per patch: a pair factor costs about
/// as much as a ray, so exact rows cost at most about kExactPatchesPerRay times the rays asked
/// for, for errors orders of magnitude smaller (docs/accuracy.md).
/// And N ≤ kExactRowsMaxPatches: exact rows hold an entry per patch a row, N² in all (3.2 GB at
/// the bound on floats, 8 bytes a nonzero), where sampled rows hold at most rays; a constant, not
/// the node's memory, so that the choice, and the answer, never depend on how the ranks are placed.
RowsChoice chooseRows(const Mesh& patches, int64_t raysPerPatch);
inline constexpr int64_t kExactPatchesPerRay = 8;
inline constexpr int64_t kExactRowsMaxPatches = 20000;
/// Exact rows' error, Σ_j |δF_ij| over the row's sum, the quoted error takes for each row's H
/// (solve/solution_error.cpp): the Gauss rules of the pairs apart by more than i's size, each
/// within 1.5e-3 of its F_ij but their errors summing to at most 6e-6 of a row on the cube
/// (192 and 6,144 patches) and on plates 1 apart to 1e-4 apart (256 to 2,048 patches); the
/// nearer pairs' contour integrals to 1e-11 (formfactor/contour_factors.h).
inline constexpr double kExactRowsRelativeError = 1e-5;
/// The most patches chooseRows() makes exact rows for at `raysPerPatch` (in a convex enclosure):
/// how far refinement can go before the rows would be sampled.
inline int64_t exactRowsPatchBound(int64_t raysPerPatch) {
  return std::min(kExactRowsMaxPatches, kExactPatchesPerRay * raysPerPatch);
}

/// Whether every vertex lies on or in front of every triangle's plane: one convex enclosure, in
/// which no patch hides another (the geometric half of chooseRows()). Refinement keeps it.
bool convexEnclosure(const Mesh& mesh);

/// Whether every vertex of the mesh lies on or in front of every triangle's plane (within 1e-9
/// of the bounding box's diagonal): then no triangle hides any part of another from a third.
bool everyPairUnoccluded(const Mesh& patches);

struct Options {
  int64_t raysPerPatch = 1024;  ///< samples per patch (kEmitterMis casts two rays per sample)
  uint64_t seed = 1;
  Estimator estimator = Estimator::kHemisphere;
  /// Samples [firstSample, firstSample + raysPerPatch) of the extensible sequence are drawn, so
  /// N samples and then M more from firstSample = N give exactly the N + M samples at once.
  int64_t firstSample = 0;
  int threads = 1;  ///< threads of this rank sharing its rows
  /// Rows by closed forms, no rays (only where chooseRows says so: nothing checks it here).
  /// Each sample scores F_ij itself, so the sums extend, merge and convert like sampled ones.
  bool exactRows = false;
  /// F's store holds floats (SplitRows::singlePrecision): exact rows are rounded onto values a
  /// float holds exactly, their sums kept (ExactRows).
  bool singlePrecision = false;
  /// Exact rows stored once a pair (SplitRows::pairsOnce): row i keeps the F_ij of the pairs it
  /// owns (ownsPair) and, as its diagonal entry, the sum of the others, which the rows that own
  /// them hold through reciprocity.
  bool pairsOnce = false;
};

/// F's rows as values (core/matrix_rows.h, so the result file takes them as they are): columns
/// sorted ascending, values F_ij (> 0 as sampled; solve::repairFormFactors may leave negative
/// entries after heavy dropping, and warns).
using radiosity::SparseRows;

/// The raw sums behind SparseRows (core/matrix_rows.h, so a checkpoint takes them as they are),
/// kept so that more samples can be added later: each sample's contribution is rounded to a
/// multiple of 2^-32 and summed as an integer, so sums are exact, independent of the order of
/// summation (threads, ranks, restarts) and simply add up.
using radiosity::SampleTally;

/// F_ij = sum / (2^32 · samples).
SparseRows toFormFactors(const SampleTally& tally);

/// True when every F_ij = sum / (2^32 · samples) of the tally, as a double, gives its sum back
/// exactly (sumFromValue): then the values are the one store F needs, and the tally can be
/// rebuilt from them for a checkpoint. It holds for sums below 2^50 (samples × F_ij < 2^18);
/// checked entry by entry, not assumed.
bool valuesKeepTheSums(const SampleTally& tally);
/// The sum behind F_ij = value over `samples` samples (exact where valuesKeepTheSums holds).
using radiosity::sumFromValue;

/// F's one store (core's SplitRows): the values in the blocks PETSc keeps, from which the tally
/// is rebuilt exactly.
using radiosity::SplitRows;

/// Below this many samples a row, every sum is below 2^50 (a sample adds at most 1 to an entry:
/// a hemisphere ray hits one patch, MIS's two weights add up to 1, an exact F_ij ≤ 1), so the
/// values give the sums back; from it on, SplitRows keeps the tally too (appendRows).
inline constexpr int64_t kExactSumSamples = int64_t{1} << 18;

/// Whether F's store may hold sampled rows' values in single precision
/// (SplitRows::singlePrecision), 8 B a nonzero instead of 12: rows of fewer than
/// kExactSumSamples samples, where rounding every F_ij by up to 2^-24 of itself moves B by at
/// most about 2^-24 / (1 − ρ_max) of itself (each bounce adds its rounding; 1 / (1 − ρ_max)
/// bounds their number) and that is below a thousandth of the sampling error's scale, N^(-2/3)
/// (docs/design/checkpoints.md, "F in single precision").
bool singlePrecisionServes(int64_t samples, double largestReflectance);

/// From this many patches on, exact rows are stored in single precision by default: F is then
/// over 200 MB at 12 B a nonzero, and most of a row's entries are below 2^-8, where a float
/// holds every multiple of 2^-32. ExactRows rounds onto floats keeping each row's sum: entries
/// from 2^-8 up move by a float's rounding (under 2^-24 of themselves, against the closed forms'
/// ~1e-6), the others by a unit or two of 2^-32 as on doubles (docs/design/checkpoints.md, "F in
/// single precision"). Below it, rows have fewer small entries to take what the large ones'
/// rounding leaves.
inline constexpr int64_t kSingleExactRowsPatches = 4096;

/// Whether exact rows (`patches` of them, `samples` samples behind their sums) may be stored in
/// single precision: from kSingleExactRowsPatches patches on, below kExactSumSamples samples.
bool singlePrecisionServesExactRows(int64_t patches, int64_t samples);

/// Whether row i stores the pair {i, j} (i ≠ j) for both (SplitRows::pairsOnce): the larger of
/// the two where i + j is odd, the smaller where even, so that every row keeps about half its
/// columns, on any rank count.
inline bool ownsPair(int64_t i, int64_t j) { return ((i + j) % 2 != 0) == (i < j); }

/// Exact rows' sums put onto values a float holds, each row keeping its sum as ExactRows keeps
/// it (roundToUnits): for rows read back from a checkpoint made on doubles, or extended by more
/// samples, before they go into a store of floats. Rows on floats already stay as they are.
void keepExactRowsOnFloats(SampleTally& rows);

/// Appends `piece` (the rows that follow, with the same samples a row, or any when `rows` holds
/// none) as values: each sum / (2^32 · samples), checked to give its sum back, unless the samples
/// reach kExactSumSamples, where the tally is kept as well (in single precision,
/// rows.singlePrecision set before the first piece, each value is rounded to a float and no sum is
/// checked). Throws Error(kUsage) where PETSc's 32-bit indices cannot hold the rows (a patch id or
/// a rank's entries of 2^31 or more), and Error(kFailure) for a value that loses its sum below
/// kExactSumSamples (a bug).
void appendRows(SplitRows& rows, const SampleTally& piece);

/// Reserves room in `rows` for `expectedRows` rows in all: twice its entries per row so far, so
/// that the arrays seldom move (a move holds both copies); the room not filled stays address
/// space, not memory.
void reserveRows(SplitRows& rows, int64_t expectedRows);

/// F_ij of the stored rows in column order (the same doubles toFormFactors gives from their
/// tally; the explicit zero diagonal left out): SplitRows::values of every row.
SparseRows toFormFactors(const SplitRows& rows);

/// The tally of both sample sets, same rows: equal to drawing them in one go.
SampleTally mergeSamples(const SampleTally& a, const SampleTally& b);

/// Reserves room in `tally` for `expectedRows` rows in all, at its entries per row so far
/// (+25 %), unless it has that room already: pages reserved and never written are not resident,
/// while a vector that doubles as it grows holds up to 2.5 times its size, and every doubling
/// copies it.
void reserveRows(SampleTally& tally, int64_t expectedRows);

/// Counts gathered while sampling (this rank's rows only).
struct Statistics {
  int64_t raysCast = 0;
  int64_t backFaceHits = 0;  ///< absorbed: many of them mean wrong winding
  /// backFaceHits split by the label of the patch whose back was hit (Mesh::labelNames order);
  /// empty if the mesh has no labels.
  std::vector<int64_t> backFaceHitsByLabel;
  int64_t escapedRays = 0;  ///< left the scene (open scenes)
  /// Of backFaceHits, those of batches whose every ray met a back: rows of patches that see
  /// nothing (hidden under an object: formfactor::hiddenPatches), or inside a model wound
  /// inside out around them.
  int64_t blindBackFaceHits = 0;
  int64_t pairFactors = 0;  ///< F_ij computed by closed forms (Options::exactRows)
  /// Exact rows on floats whose entries could not take what rounding onto floats left over
  /// (too few below 2^-8): off their sum by less than 2^-24 of it (formfactor::roundToUnits).
  int64_t rowsOffTheirSum = 0;
  /// Over the rows given to addRowSums (+∞ for the minimum until there is one).
  double minRowSum = std::numeric_limits<double>::infinity(), maxRowSum = 0, sumRowSums = 0;
};

/// Called now and then with the number of this rank's rows finished so far.
using ProgressCallback = std::function<void(int64_t rowsDone)>;

/// Samples the rows of the patches [firstPatch, endPatch). Hemisphere sampling: from
/// stratified points, F_ij ≈ (rays whose first hit is the front of j) / N. Every random number
/// comes from an Owen-scrambled Sobol' sequence keyed by (seed, global patch id) and indexed by
/// the sample number, so a row is the same whichever rank or thread computes it.
SampleTally sampleRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress = {});

/// Samples rows piece by piece with one setup (emitter table, normals, each thread's buffers),
/// for work split at safe points or extended by more samples later. Rows [firstPatch, endPatch),
/// samples [firstSample, firstSample + count) of the extensible sequence; the tally is the same
/// as sampleRows() with those options.
class RowSampling {
 public:
  RowSampling(const SceneTracer& tracer, const Mesh& patches, const Options& options);
  ~RowSampling();
  RowSampling(const RowSampling&) = delete;
  RowSampling& operator=(const RowSampling&) = delete;

  SampleTally sample(int64_t firstPatch, int64_t endPatch, int64_t firstSample, int64_t count,
                     Statistics& statistics, const ProgressCallback& progress = {});
  /// The same rows appended to `tally`, which must end where they begin (firstPatch) and hold
  /// `count` samples per row, or hold no rows (it then starts at firstPatch): the rows are
  /// written in place, not copied from a tally of their own.
  void sampleInto(SampleTally& tally, int64_t firstPatch, int64_t endPatch, int64_t firstSample,
                  int64_t count, Statistics& statistics, const ProgressCallback& progress = {});

  /// Makes the light choices of the clusters of rows [firstPatch, endPatch) now (sample() makes
  /// those it lacks itself): for callers that time sample() and want the rows' cost alone.
  void chooseLights(int64_t firstPatch, int64_t endPatch);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Each row's Σ_j F_ij, summed in column order (the same doubles from the rows and from the
/// tally behind them).
std::vector<double> rowSums(const SparseRows& rows);
std::vector<double> rowSums(const SampleTally& tally);
std::vector<double> rowSums(const SplitRows& rows);

/// Adds the rows' sums Σ_j F_ij to the min/max/sum of `statistics`.
void addRowSums(const SparseRows& rows, Statistics& statistics);
void addRowSums(const std::vector<double>& rowSums, Statistics& statistics);

/// The hemisphere rays sampleRows() casts from `patch` for samples [firstSample, firstSample +
/// count), into `rays`: for benchmarks that trace the same rays bare.
void hemisphereRays(const Mesh& patches, int64_t patch, int64_t firstSample, int64_t count,
                    uint64_t seed, double offset, SceneTracer::RayBatch& rays);

/// The offset sampleRows() puts between a ray's origin on `patch` and its surface.
inline double rayOffset(const SceneTracer& tracer, int64_t patch) { return tracer.offset(patch); }

/// 1 for each patch of [firstPatch, endPatch) that sees nothing: every one of a few dozen rays
/// from points spread over it meets the back of a face (the floor under a block standing on it,
/// once cut along the block's walls; a face inside a closed solid). No light reaches such a
/// patch and none it reflects leaves, so the solve leaves it out (B = E) and the result marks it.
/// Rays of their own (a fixed seed), so the answer depends on the mesh only, not on --seed, the
/// rank or the thread; at most 64 rays a hidden patch, mostly 1–4 for the others.
std::vector<uint8_t> hiddenPatches(const SceneTracer& tracer, const Mesh& patches,
                                   int64_t firstPatch, int64_t endPatch);

/// Counts of rows whose Σ_j F_ij falls in each bin of rowSumBinEdges() (this rank's rows).
std::vector<int64_t> rowSumHistogram(const SparseRows& rows);
std::vector<int64_t> rowSumHistogram(const std::vector<double>& rowSums);
/// Bin edges: [0, 0.5), [0.5, 0.9), [0.9, 0.99), [0.99, 0.999), [0.999, 1 − 1e-9),
/// [1 − 1e-9, 1 + 1e-9] (closed to round-off), (1 + 1e-9, ∞).
const std::vector<double>& rowSumBinEdges();

}  // namespace radiosity::formfactor
