// Private to solve/: rays from each of a rank's rows, traced on the rank's threads, for the
// discretisation estimate's passes (the direct light's shadow rays, the gathering rays).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "trace/parallel_for.h"
#include "trace/sample_warps.h"
#include "trace/trace.h"

namespace radiosity::solve {

// Rows a thread takes at a time: enough that handing out a piece costs little beside its rays.
constexpr int64_t kRowsPerTracePiece = 256;

// For each owned patch i, on `threads` threads: `aim(i, frame, offset, rays, slot)` sets its
// `perPatch` rays (offset: how far their origins lie off the patch), which are traced, then
// `score(i, frame, rays, hits, slot)`. `slot` names the thread (trace::parallelFor), so what the
// callbacks keep per slot needs no lock; what they add up across rows must not depend on the
// order (integer sums), so that the estimate is the same on any number of threads.
template <class Aim, class Score>
void traceOwnedPatches(const trace::SceneTracer& tracer, const Mesh& patches,
                       partition::PatchRange owned, int64_t perPatch, int threads, const Aim& aim,
                       const Score& score) {
  struct Batches {
    trace::SceneTracer::RayBatch rays;
    trace::SceneTracer::HitBatch hits;
  };
  std::vector<Batches> slots(static_cast<size_t>(std::max(threads, 1)));
  trace::parallelFor(
      owned.size(), threads,
      [&](int64_t begin, int64_t end, int slot) {
        Batches& batch = slots[slot];
        if (batch.rays.size() != static_cast<size_t>(perPatch)) batch.rays.resize(perPatch);
        for (int64_t i = owned.begin + begin; i < owned.begin + end; ++i) {
          const trace::PatchFrame frame(patches, i);
          aim(i, frame, formfactor::rayOffset(tracer, i), batch.rays, slot);
          tracer.intersect(batch.rays, batch.hits);
          score(i, frame, batch.rays, batch.hits, slot);
        }
      },
      kRowsPerTracePiece);
}

}  // namespace radiosity::solve
