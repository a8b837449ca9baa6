// The mesh stage, shared by `radiosity solve` (run/solve_setup_stages.cpp) and `radiosity study`
// (jobs/study/study_command.cpp): the scene cut along its contacts and refined into patches
// numbered along a space-filling curve. One function of the scene and how to mesh it, so that a
// study meshes exactly as a solve does and a solve's result can be a study's reference.
#pragma once

#include <cstdint>

#include "core/mesh.h"
#include "partition/partition.h"
#include "run/console.h"

namespace radiosity::run {

/// What the stage meshes and how. `console` (not owned) shows the progress of a long contact
/// search and the contact lines (rank 0's: every rank meshes alike).
struct MeshJob {
  const Console& console;
  Mesh scene;  ///< the scene as loaded, moved in: freed once refined
  /// The area bound (partition::refine); not used when `patches` > 0.
  double maxArea = 0;
  /// > 0: about this many patches (partition::refineToCount), whose area bound meshing finds.
  int64_t patches = 0;
  /// Cut along contacts first (cutAlongContacts in run/mesh_stage.cpp): `--contacts cut`, the
  /// default; false: the scene as given, refined uniformly.
  bool cutContacts = true;
  /// partition::refine's surface share: patches shared among the smooth surfaces (solve's
  /// kAutoSurfaceShare without --max-area; 0 with it, and in a study).
  int64_t surfaceShare = 0;
};

/// What cutting along contacts did, for the log.
struct ContactsCut {
  bool cut = false;  ///< false: the scene as given (a convex enclosure, or --contacts off)
  partition::ContactReport report;
  size_t edges = 0;    ///< the edges along contact lines, refined to a quarter of the bound
  double seconds = 0;  ///< this rank's time in finding and cutting them
};

/// What the stage made.
struct MeshedScene {
  Mesh patches;  ///< refined and numbered along the curve (partition::orderAlongCurve)
  /// The meshing's counts and quality; its areaBound is the bound --patches chose.
  partition::MeshingReport meshing;
  ContactsCut contacts;
};

/// Meshes `job.scene`: cut along its contacts (if job.cutContacts; the contact lines printed by
/// reportCovered and reportContacts, as the cut is made), refined to job.maxArea or to about
/// job.patches patches (patches along contact lines to a quarter of the bound), the scene freed,
/// and the patches ordered along the curve. The same on every rank; a failure on any rank fails
/// every rank (runCollectively). Collective.
MeshedScene meshScene(MeshJob job);

}  // namespace radiosity::run
