#include "run/checkpointing.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <iterator>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "formfactor/formfactor.h"
#include "run/request_options.h"

namespace radiosity::run {

namespace {

template <class T>
void mix(size_t& hash, const std::vector<T>& values) {
  const std::string_view bytes(reinterpret_cast<const char*>(values.data()),
                               values.size() * sizeof(T));
  hash = hash * 1099511628211u ^ std::hash<std::string_view>{}(bytes);
}

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

std::map<std::string, std::string> runIdentity(const SolveRequest& settings, const RunPlan& plan,
                                               const Mesh& patches, double maxArea) {
  // The geometry and the materials apart: F depends on the first only, so a checkpoint's rows
  // serve a run with other materials (reflectance, emission, thermal conditions).
  size_t hash = 14695981039346656037u, materials = hash;
  mix(hash, patches.vertices);
  mix(hash, patches.triangles);
  mix(hash, patches.sourceFace);
  mix(materials, patches.reflectance);
  mix(materials, patches.emission);
  char fingerprint[80], materialPrint[40];
  std::snprintf(fingerprint, sizeof fingerprint, "%lld patches, hash %016zx",
                static_cast<long long>(patches.triangleCount()), hash);
  std::snprintf(materialPrint, sizeof materialPrint, "hash %016zx", materials);
  std::map<std::string, std::string> identity = {
      {"scene", fingerprint},
      {kMaterials, materialPrint},
      {"mis light choice", formfactor::misLightChoice()},
      {"rows", !plan.exactRows  ? "sampled"
               : plan.pairsOnce ? "exact (closed forms, a convex scene), each pair stored once"
                                : "exact (closed forms, a convex scene)"}};
  // and every option declared part of it (run/request_options.cpp)
  const RunShown shown{settings, plan, maxArea};
  for (const RequestOption& option : requestOptions())
    if (option.identity) identity[option.key()] = option.identity(shown);
  return identity;
}

std::string meshInput(const SolveRequest& settings, const Mesh& scene, double maxArea) {
  size_t hash = 14695981039346656037u;
  mix(hash, scene.vertices);
  mix(hash, scene.triangles);
  mix(hash, scene.sourceFace);
  char text[160];
  std::snprintf(text, sizeof text, "%lld triangles, hash %016zx, max-area %s, contacts %s",
                static_cast<long long>(scene.triangleCount()), hash, number(maxArea).c_str(),
                settings.cutContacts ? "cut" : "not cut");
  return text;
}

std::optional<Mesh> meshFromCheckpoint(const std::string& path, CheckpointMesh saved,
                                       const Mesh& scene) {
  // The first triangle of each of the scene's faces, whose materials the patches of the face
  // take: only where every triangle of a face has the same (a scene file may give a face's
  // triangles materials of their own, which the patches do not tell apart).
  int64_t faces = 0;
  for (int64_t f : scene.sourceFace) faces = std::max(faces, f + 1);
  std::vector<int64_t> firstOf(static_cast<size_t>(faces), -1);
  for (int64_t t = scene.triangleCount() - 1; t >= 0; --t) firstOf[scene.sourceFace[t]] = t;
  const bool labelled = scene.hasLabels();
  for (int64_t t = 0; t < scene.triangleCount(); ++t) {
    const int64_t first = firstOf[scene.sourceFace[t]];
    if (scene.reflectance[t] != scene.reflectance[first] ||
        scene.emission[t] != scene.emission[first] ||
        (labelled && scene.label[t] != scene.label[first]))
      return std::nullopt;
  }
  Mesh mesh;
  mesh.vertices = std::move(saved.vertices);
  mesh.triangles = std::move(saved.triangles);
  mesh.sourceFace = std::move(saved.sourceFace);
  for (int64_t f : mesh.sourceFace) {
    const int64_t t = f < faces ? firstOf[f] : -1;
    if (t < 0)
      throw InputError(path + ": corrupted checkpoint: a patch of its mesh comes from face " +
                       std::to_string(f) + ", which the scene does not have");
    mesh.reflectance.push_back(scene.reflectance[t]);
    mesh.emission.push_back(scene.emission[t]);
    if (labelled) mesh.label.push_back(scene.label[t]);
  }
  mesh.labelNames = scene.labelNames;
  mesh.labelEmissivity = scene.labelEmissivity;
  mesh.lengthUnit = scene.lengthUnit;
  mesh.sourceFiles = scene.sourceFiles;
  return mesh;
}

namespace {
// The keys of the identity that the patches make: where one differs, the others may follow.
constexpr const char* kMeshKeys[] = {kContacts, "scene"};
}  // namespace

bool checkResumable(const std::string& path, const Checkpoint& saved,
                    const std::map<std::string, std::string>& identity, int64_t patchCount,
                    int64_t raysPerPatch) {
  std::ostringstream differences, meshDifferences;
  bool otherMaterials = false;
  for (const auto& [key, value] : identity) {
    auto found = saved.identity.find(key);
    if (key == kMaterials) {
      otherMaterials = found == saved.identity.end() || found->second != value;
      continue;
    }
    // (checkpoints of versions that did not record it: the scene's fingerprint tells)
    if (key == kContacts && found == saved.identity.end()) continue;
    const std::string before = found == saved.identity.end() ? "(none)" : found->second;
    if (before == value) continue;
    const bool ofTheMesh =
        std::find(std::begin(kMeshKeys), std::end(kMeshKeys), key) != std::end(kMeshKeys);
    (ofTheMesh ? meshDifferences : differences)
        << "; " << key << ": " << before << " there, " << value << " now";
  }
  for (const auto& [key, value] : saved.identity) {
    if (identity.count(key) == 0)
      differences << "; " << key << ": " << value << " there, (none) now";
  }
  // Where the patches differ, what follows from them (the area bound of the default mesh, the
  // estimator chosen for it) is not news: the cause is named first, the rest said to follow.
  if (!meshDifferences.str().empty())
    throw InputError(
        path + ": a checkpoint of another scene or mesh" + meshDifferences.str() +
        (differences.str().empty()
             ? std::string()
             : "; and (which the patches choose where not given) " + differences.str().substr(2)) +
        " (only --rays and the materials may change on a restart)");
  if (!differences.str().empty() || saved.patchCount != patchCount) {
    throw InputError(path + ": a checkpoint of another scene or other options" + differences.str() +
                     " (only --rays and the materials may change on a restart)");
  }
  for (int64_t samples : saved.rows.rowSamples) {
    if (samples > raysPerPatch) {
      throw InputError(path + ": its rows hold " + std::to_string(samples) +
                       " samples, more than --rays " + std::to_string(raysPerPatch) +
                       " (a restart may add rays, not remove them)");
    }
  }
  return otherMaterials;
}

std::optional<SolveProgress> resumableProgress(const Checkpoint& saved, int64_t raysPerPatch,
                                               MPI_Comm comm) {
  if (!saved.progress.started()) return std::nullopt;
  bool sameRows = true;
  for (int64_t samples : saved.rows.rowSamples) sameRows = sameRows && samples == raysPerPatch;
  int allSame = sameRows ? 1 : 0;  // every rank must resume alike
  MPI_Allreduce(MPI_IN_PLACE, &allSame, 1, MPI_INT, MPI_MIN, comm);
  SolveProgress progress = saved.progress;
  if (allSame == 0) {  // F has more samples now: the saved B is only a good first guess
    for (int& state : progress.channelState) state = state == 0 ? 0 : 1;
  }
  return progress;
}

}  // namespace radiosity::run
