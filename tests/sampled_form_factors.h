// Rows of F in one call, for tests and benchmarks. The program samples its rows in pieces with
// safe points (jobs/formfactor_stage.h); sampled in one go they are the same, bit for bit.
#pragma once

#include <cstdint>

#include "formfactor/formfactor.h"

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

}  // namespace radiosity::testing
