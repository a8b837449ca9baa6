// The pieces shared by the solve pipeline and the study (see pipeline_parts.h).
#include "run/pipeline_parts.h"

#include <cstdio>

#include "parallel/collective.h"

namespace radiosity::run {

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

Contacts cutAlongContacts(Mesh& scene, const Console& console) {
  Contacts contacts;
  const bool convex = scene.triangleCount() <= formfactor::kExactRowsMaxPatches &&
                      formfactor::convexEnclosure(scene);
  if (!convex)
    console.info("contacts: finding where the " + std::to_string(scene.triangleCount()) +
                 " triangles touch or cross each other");
  // Each part's pace from its first call on (what comes before it is another pace).
  std::string part;
  double first = 0, shown = 0;
  int64_t firstDone = 0;
  auto progress = [&](const char* what, int64_t done, int64_t whole) {
    const double now = MPI_Wtime();
    if (part != what) part = what, first = shown = now, firstDone = done;
    if (now - shown < 2.0 || done == firstDone) return;
    shown = now;
    const double left =
        (now - first) * static_cast<double>(whole - done) / static_cast<double>(done - firstDone);
    char line[160];
    std::snprintf(line, sizeof line, "  contacts: %lld/%lld %s, about %.0f s left",
                  static_cast<long long>(done), static_cast<long long>(whole), what, left);
    console.info(line);
  };
  Mesh cut = partition::cutAtContacts(scene, &contacts.report, progress);
  // A convex enclosure is cut only where a face lies over another (a lamp panel flush on its
  // ceiling): nothing else touches in it.
  // (its rows may be exact: no finer patches along its own corners).
  if (convex && contacts.report.covered.empty()) return Contacts{};
  scene = std::move(cut);
  contacts.cut = true;
  if (convex) return contacts;
  console.info("  contacts: finding the edges along contact lines");
  contacts.edges = partition::contactEdges(scene);
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

}  // namespace radiosity::run
