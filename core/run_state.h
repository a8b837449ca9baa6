// What a run has done so far, in the shapes the stages hand on and a checkpoint stores: the rows
// of F sampled (with how many samples each), and the solve's progress (with its history).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/matrix_rows.h"
#include "core/vec3.h"

namespace radiosity {

/// The solver's convergence history, the same on every rank: one entry per iteration of each
/// channel solved. Stored as /solve/history, float64 [n,4] with columns channel (0 red, 1 green,
/// 2 blue), iteration, relative residual, seconds since the start of the solve; the dataset's
/// attribute `columns` names them.
struct SolveHistory {
  std::vector<int> channel;
  std::vector<int64_t> iteration;
  std::vector<double> residual;
  std::vector<double> seconds;
  size_t size() const { return residual.size(); }
};

/// This rank's rows of F in some state of completion: rowSamples[r] samples are behind row r's
/// sums (0: not sampled yet, the row is empty). Rows may have different numbers of samples (a
/// restart with more rays extends them a piece at a time), so tally.samples is not used. Rows
/// sampled to the end are held as F's one store instead (`values`, every row with rowSamples
/// samples; `tally` then empty), whose tally a checkpoint rebuilds a piece at a time.
struct SampledRows {
  SampleTally tally;
  SplitRows values;
  std::vector<int64_t> rowSamples;
  int64_t rowsFinished() const {  ///< rows with rowSamples > 0
    return std::count_if(rowSamples.begin(), rowSamples.end(), [](int64_t s) { return s > 0; });
  }
};

/// The adaptive refinement rounds done so far: round r split the patches
/// marked[roundStart[r] .. roundStart[r + 1]) of the mesh it started from (partition::
/// refineMarked), most urgent first, to patchesAfter[r] patches (refineMarked with that budget
/// gives the round again, whatever budget cut it), then undid the bisections at the vertices
/// merged[mergedStart[r] .. mergedStart[r + 1]) of that refined mesh, where the light was flat
/// (partition::undoBisections). The mesh of a run is its first mesh taken through these rounds
/// in turn, so a restart replays them instead of storing the mesh.
struct RefinementHistory {
  std::vector<int64_t> roundStart{0};
  std::vector<int64_t> marked;
  std::vector<int64_t> patchesAfter;
  std::vector<int64_t> mergedStart{0};
  std::vector<int64_t> merged;
  /// Per round: the rays per patch its rows are sampled at, and the estimated discretisation
  /// error of the solve that led to it (both empty in checkpoints of earlier versions), so that
  /// a restart goes on as the run would have.
  std::vector<int64_t> raysAfter;
  std::vector<double> estimateBefore;
  int rounds() const { return static_cast<int>(roundStart.size()) - 1; }
  std::vector<int64_t> round(int r) const {
    return {marked.begin() + roundStart[r], marked.begin() + roundStart[r + 1]};
  }
  std::vector<int64_t> merges(int r) const {
    return {merged.begin() + mergedStart[r], merged.begin() + mergedStart[r + 1]};
  }
  void add(const std::vector<int64_t>& marks, int64_t patches, int64_t rays = 0,
           double estimate = 0) {
    marked.insert(marked.end(), marks.begin(), marks.end());
    roundStart.push_back(static_cast<int64_t>(marked.size()));
    patchesAfter.push_back(patches);
    mergedStart.push_back(static_cast<int64_t>(merged.size()));
    raysAfter.push_back(rays);
    estimateBefore.push_back(estimate);
  }
  /// The rays per patch of the last round, 0 where not recorded.
  int64_t lastRays() const { return raysAfter.empty() ? 0 : raysAfter.back(); }
  /// The estimated discretisation error the last round was taken on, 0 where not recorded.
  double lastEstimate() const { return estimateBefore.empty() ? 0 : estimateBefore.back(); }
  /// The bisections the last round undid.
  void addMerges(const std::vector<int64_t>& vertices) {
    merged.insert(merged.end(), vertices.begin(), vertices.end());
    mergedStart.back() = static_cast<int64_t>(merged.size());
  }
};

/// How far the solve got, and what a restart resumes from.
struct SolveProgress {
  std::array<int, 3> channelState{};  ///< per channel: 0 not started, 1 in progress, 2 done
  /// This rank's rows of B: the answer of the channels done, the iterate of the one in progress
  /// (0 for channels not started).
  std::vector<Rgb> radiosity;
  SolveHistory history;
  bool started() const { return channelState != std::array<int, 3>{0, 0, 0}; }
};

}  // namespace radiosity
