// The tracing stage (see tracing_stage.h): the tracer, the split, the hidden patches, the owned
// patches' data.
#include "run/tracing_stage.h"

#include <mpi.h>

#include "formfactor/formfactor.h"
#include "parallel/collective.h"

namespace radiosity::run {

namespace {

/// Which patches see nothing (formfactor::hiddenPatches), for every patch on every rank: each
/// rank probes its own rows `owned` and the flags are gathered. Collective.
std::vector<uint8_t> findHiddenPatches(MPI_Comm comm, const trace::SceneTracer& tracer,
                                       const Mesh& patches, partition::PatchRange owned) {
  const std::vector<uint8_t> mine =
      formfactor::hiddenPatches(tracer, patches, owned.begin, owned.end);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  // Blocks tile [0, np) in rank order; a block's size fits an int (2^31 patches a rank).
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(ranks), offsets(ranks, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<uint8_t> all(patches.triangleCount());
  MPI_Allgatherv(mine.data(), count, MPI_UINT8_T, all.data(), counts.data(), offsets.data(),
                 MPI_UINT8_T, comm);
  return all;
}

/// The data of the rows `owned` of `patches`, the hidden ones' ρ set to 0.
OwnedPatches ownedPatches(const Mesh& patches, partition::PatchRange owned,
                          const std::vector<uint8_t>& hidden) {
  OwnedPatches mine;
  mine.area.resize(owned.size());
  for (int64_t r = 0; r < owned.size(); ++r) mine.area[r] = patches.area(owned.begin + r);
  mine.reflectance.assign(patches.reflectance.begin() + owned.begin,
                          patches.reflectance.begin() + owned.end);
  mine.emission.assign(patches.emission.begin() + owned.begin,
                       patches.emission.begin() + owned.end);
  for (int64_t r = 0; r < owned.size(); ++r)
    if (hidden[owned.begin + r]) mine.reflectance[r] = Rgb{0, 0, 0};
  return mine;
}

}  // namespace

TracedRows layOutRows(const TracingJob& job) {
  TracedRows laid;
  runCollectively(job.console.comm(), [&] {
    laid.tracer = std::make_unique<trace::SceneTracer>(job.patches, job.threads);
  });
  const int64_t patchCount = job.patches.triangleCount();
  const partition::Blocks blocks =
      job.split ? job.split(*laid.tracer)
                : partition::Blocks::byCount(patchCount, job.console.ranks());
  laid.owned = blocks.of(job.console.rank());
  laid.hidden = findHiddenPatches(job.console.comm(), *laid.tracer, job.patches, laid.owned);
  laid.local = ownedPatches(job.patches, laid.owned, laid.hidden);
  return laid;
}

}  // namespace radiosity::run
