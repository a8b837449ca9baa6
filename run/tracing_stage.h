// The tracing stage, shared by `radiosity solve` (run/solve_setup_stages.cpp, for each round's
// mesh) and `radiosity study` (jobs/study/study_command.cpp, for each mesh): the BVH over the
// patches, this rank's rows, the patches that see nothing and the owned patches' data the solve
// takes. One function of the patches and how the rows are split, so that the two cannot drift
// apart.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/mesh.h"
#include "partition/partition.h"
#include "run/console.h"
#include "trace/trace.h"

namespace radiosity::run {

/// How the rows are split among the ranks, once the tracer is built: solve cuts them by
/// measured cost (balanceRows, run/rank_balance.h), which needs the tracer. The same on every
/// rank; may be collective.
using RowSplit = std::function<partition::Blocks(const trace::SceneTracer& tracer)>;

/// What the stage lays out. Not owned.
struct TracingJob {
  const Console& console;
  /// Every patch, in the tracing frame (normaliseForTracing), as the stage's tracer sees them.
  const Mesh& patches;
  int threads = 0;  ///< the tracer's threads per rank
  /// The split; empty: by count (partition::blockOf), as `radiosity study` splits.
  RowSplit split = {};
};

/// What the solve needs of each owned patch: its area (in the tracing frame, like the form
/// factors'), reflectance and emission.
struct OwnedPatches {
  std::vector<double> area;
  std::vector<Rgb> reflectance, emission;
};

/// What the stage made.
struct TracedRows {
  /// The BVH over every patch of job.patches, built on every rank (job.threads each).
  std::unique_ptr<trace::SceneTracer> tracer;
  partition::PatchRange owned;  ///< this rank's rows
  /// 1 for each patch that sees nothing (under an object, inside a solid), every patch
  std::vector<uint8_t> hidden;
  /// The owned rows' data, the hidden ones' ρ set to 0: they are left out of the solve (B = E
  /// exactly, whatever stray rays their rows caught; the result keeps their ρ).
  OwnedPatches local;
};

/// Builds the tracer over job.patches (a failure on any rank fails every rank), splits the rows
/// by job.split, finds which patches see nothing (formfactor::hiddenPatches: each rank probes
/// its own rows and the flags are gathered) and takes the owned rows' data. Collective.
TracedRows layOutRows(const TracingJob& job);

}  // namespace radiosity::run
