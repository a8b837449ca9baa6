// The mesh stage (see mesh_stage.h): contacts cut, the scene refined, the patches ordered.
#include "run/mesh_stage.h"

#include <cstdio>
#include <string>
#include <utility>

#include "formfactor/formfactor.h"
#include "parallel/collective.h"
#include "run/stage_reports.h"

namespace radiosity::run {

namespace {

/// What cutAlongContacts() did: the edges along contact lines, for partition::refine().
struct Contacts {
  bool cut = false;  ///< false: the scene as given (a convex enclosure), refined uniformly
  partition::ContactReport report;
  partition::ContactEdges edges;
};

/// Cuts `scene` along its contacts and finds the edges along them (partition::cutAtContacts,
/// contactEdges), as `solve` meshes by default and `study` with it (so that a solve's result can
/// be a study's reference). Not in a convex enclosure of up to kExactRowsMaxPatches triangles
/// (an empty room, a furnace): nothing stands in it, and its rows may be exact
/// (formfactor::chooseRows), so its mesh stays uniform and its own corners do not push it past
/// exact rows. A function of the geometry only, not of --exact-rows. `console` shows the
/// progress of a long search (rank 0's: every rank cuts alike).
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

}  // namespace

MeshedScene meshScene(MeshJob job) {
  MeshedScene meshed;
  runCollectively(job.console.comm(), [&] {
    Contacts contacts;
    if (job.cutContacts) {
      const double start = MPI_Wtime();
      contacts = cutAlongContacts(job.scene, job.console);
      const double seconds = MPI_Wtime() - start;
      if (contacts.cut) {
        reportCovered(job.console, job.scene, contacts.report);
        reportContacts(job.console, contacts.report, contacts.edges.size(), seconds);
      }
      meshed.contacts = {contacts.cut, std::move(contacts.report), contacts.edges.size(), seconds};
    }
    const partition::ContactEdges* edges = contacts.cut ? &contacts.edges : nullptr;
    Mesh refined =
        job.patches > 0
            ? partition::refineToCount(job.scene, job.patches, &meshed.meshing, edges)
            : partition::refine(job.scene, job.maxArea, &meshed.meshing, edges, job.surfaceShare);
    job.scene = Mesh();  // not needed any more: free it before the reordered copy
    meshed.patches = partition::orderAlongCurve(std::move(refined));
  });
  return meshed;
}

}  // namespace radiosity::run
