// The small pieces `radiosity solve` (run/solve_pipeline.cpp) and `radiosity study`
// (jobs/study/study_command.cpp) are both built from, written once so that the two cannot drift
// apart: which rows a rank owns and their per-patch data, and the tracer over the whole scene.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "run/console.h"

namespace radiosity::run {

/// The rows of the patches `console`'s rank owns by count (partition::blockOf of `patchCount`),
/// as `radiosity study` takes them.
partition::PatchRange ownedRows(const Console& console, int64_t patchCount);

/// The rows of the patches `console`'s rank owns under `blocks` (run/rank_balance.h makes them).
partition::PatchRange ownedRows(const Console& console, const partition::Blocks& blocks);

/// What the solve needs of each owned patch: its area, reflectance and emission.
struct OwnedPatches {
  std::vector<double> area;
  std::vector<Rgb> reflectance, emission;
};

/// The data of the rows `owned` of `patches`, taken after normaliseForTracing (the areas are
/// those of the tracing frame, like the form factors').
OwnedPatches ownedPatches(const Mesh& patches, partition::PatchRange owned);

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
Contacts cutAlongContacts(Mesh& scene, const Console& console);

/// Which patches see nothing (formfactor::hiddenPatches), for every patch on every rank: each
/// rank probes its own rows `owned` and the flags are gathered. Collective.
std::vector<uint8_t> findHiddenPatches(MPI_Comm comm, const trace::SceneTracer& tracer,
                                       const Mesh& patches, partition::PatchRange owned);

/// Leaves the hidden ones among the owned patches out of the solve: their ρ becomes 0 there, so
/// B = E exactly, whatever stray rays their rows caught (the result keeps their ρ).
void leaveOutHidden(OwnedPatches& mine, partition::PatchRange owned,
                    const std::vector<uint8_t>& hidden);

/// The BVH over the whole scene, built on every rank (`threads` per rank); a failure on any
/// rank fails every rank (runCollectively).
std::unique_ptr<trace::SceneTracer> buildTracer(const Console& console, const Mesh& patches,
                                                int threads);

}  // namespace radiosity::run
