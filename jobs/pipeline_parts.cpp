// The pieces shared by the solve pipeline and the study (see pipeline_parts.h).
#include "jobs/pipeline_parts.h"

#include "io/store/collective.h"

namespace radiosity::jobs {

partition::PatchRange ownedRows(const Console& console, int64_t patchCount) {
  return partition::blockOf(patchCount, console.rank(), console.ranks());
}

partition::PatchRange ownedRows(const Console& console, const partition::Blocks& blocks) {
  return blocks.of(console.rank());
}

OwnedPatches ownedPatches(const Mesh& patches, partition::PatchRange owned) {
  OwnedPatches mine;
  mine.area.resize(owned.size());
  for (int64_t r = 0; r < owned.size(); ++r) mine.area[r] = patches.area(owned.begin + r);
  mine.reflectance.assign(patches.reflectance.begin() + owned.begin,
                          patches.reflectance.begin() + owned.end);
  mine.emission.assign(patches.emission.begin() + owned.begin,
                       patches.emission.begin() + owned.end);
  return mine;
}

std::unique_ptr<formfactor::SceneTracer> buildTracer(const Console& console, const Mesh& patches,
                                                     int threads) {
  std::unique_ptr<formfactor::SceneTracer> tracer;
  runCollectively(console.comm(),
                  [&] { tracer = std::make_unique<formfactor::SceneTracer>(patches, threads); });
  return tracer;
}

}  // namespace radiosity::jobs
