// What ties a checkpoint to its run: the identity a restart must match, and what of a saved
// solve a restart can take.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "core/mesh.h"
#include "io/store/checkpoint.h"
#include "run/run_plan.h"
#include "run/solve_request.h"

namespace radiosity::run {

/// The identity's key of the materials' fingerprint (reflectance and emission).
inline constexpr char kMaterials[] = "materials";
/// The identity's key of whether contacts were cut (absent in checkpoints of earlier versions).
inline constexpr char kContacts[] = "contacts";

/// The scene's fingerprints (a hash of the patches' geometry, and one of their materials) and
/// every option that changes the answer, except --rays (a restart may add rays).
std::map<std::string, std::string> runIdentity(const SolveRequest& settings, const RunPlan& plan,
                                               const Mesh& patches, double maxArea);

/// The fingerprint of the scene as loaded and of the options that mesh it (contacts cut or not,
/// the area bound), for CheckpointMesh::input: patches made from the same are the same.
std::string meshInput(const SolveRequest& settings, const Mesh& scene, double maxArea);

/// The patches of `saved` with the materials, labels and units of `scene` (of the same input,
/// meshInput()), each patch taking its source face's; none where some face's triangles differ
/// in them (the patches cannot tell which they came from: the scene is meshed again).
/// InputError naming `path` where a patch's source face is none of the scene's (damage).
std::optional<Mesh> meshFromCheckpoint(const std::string& path, CheckpointMesh saved,
                                       const Mesh& scene);

/// Refuses (InputError, exit code 3) a checkpoint of another scene or of other options, naming
/// each difference, and one with more samples per row than --rays asks for. True when only the
/// materials differ (its form factors serve; its solve does not).
bool checkResumable(const std::string& path, const Checkpoint& saved,
                    const std::map<std::string, std::string>& identity, int64_t patchCount,
                    int64_t raysPerPatch);

/// The solve's progress to resume from: as saved when every row has `raysPerPatch` samples;
/// when rays were added (F changed), the saved B only as the starting iterate of each channel.
/// None if the solve had not started. Collective on `comm`.
std::optional<SolveProgress> resumableProgress(const Checkpoint& saved, int64_t raysPerPatch,
                                               MPI_Comm comm);

}  // namespace radiosity::run
