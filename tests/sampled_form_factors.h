// Rows of F in one call, or into a store piece by piece, for tests and benchmarks. The program
// samples its rows in pieces with safe points (run/formfactor_stage.h); sampled in one go they
// are the same, bit for bit.
#pragma once

#include <algorithm>
#include <cstdint>

#include "formfactor/formfactor.h"
#include "partition/partition.h"

namespace radiosity::testing {

/// Rows [firstPatch, endPatch) of F (formfactor::sampleRows), their sums added to `statistics`.
inline formfactor::SparseRows sampledFormFactors(const trace::SceneTracer& tracer,
                                                 const Mesh& patches, int64_t firstPatch,
                                                 int64_t endPatch,
                                                 const formfactor::Options& options,
                                                 formfactor::Statistics& statistics) {
  formfactor::SparseRows rows = formfactor::toFormFactors(
      formfactor::sampleRows(tracer, patches, firstPatch, endPatch, options, statistics));
  formfactor::addRowSums(rows, statistics);
  return rows;
}

/// Rows `owned` of `patches` sampled with `options` into `store` in pieces of 37 rows, as the
/// form-factor stage fills it; the caller sets how the store holds them (precision, pairs once).
inline void sampleIntoStore(const trace::SceneTracer& tracer, const Mesh& patches,
                            partition::PatchRange owned, const formfactor::Options& options,
                            formfactor::SplitRows& store) {
  formfactor::Statistics statistics;
  formfactor::RowSampling sampling(tracer, patches, options);
  store.firstRow = owned.begin;
  store.endRow = owned.end;
  for (int64_t first = owned.begin; first < owned.end; first += 37)
    formfactor::appendRows(store, sampling.sample(first, std::min(owned.end, first + 37), 0,
                                                  options.raysPerPatch, statistics));
}

}  // namespace radiosity::testing
