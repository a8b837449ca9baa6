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

Contacts cutAlongContacts(Mesh& scene) {
  Contacts contacts;
  if (scene.triangleCount() <= formfactor::kExactRowsMaxPatches &&
      formfactor::convexEnclosure(scene))
    return contacts;
  scene = partition::cutAtContacts(scene, &contacts.report);
  contacts.edges = partition::contactEdges(scene);
  contacts.cut = true;
  return contacts;
}

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

void leaveOutHidden(OwnedPatches& mine, partition::PatchRange owned,
                    const std::vector<uint8_t>& hidden) {
  for (int64_t r = 0; r < owned.size(); ++r)
    if (hidden[owned.begin + r]) mine.reflectance[r] = Rgb{0, 0, 0};
}

std::unique_ptr<trace::SceneTracer> buildTracer(const Console& console, const Mesh& patches,
                                                int threads) {
  std::unique_ptr<trace::SceneTracer> tracer;
  runCollectively(console.comm(),
                  [&] { tracer = std::make_unique<trace::SceneTracer>(patches, threads); });
  return tracer;
}

}  // namespace radiosity::jobs
