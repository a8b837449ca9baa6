// The scene the form-factor benchmarks trace, from the environment (defaults: the Cornell box at
// 5000 patches, 256 rays a patch), so that they can be measured as scenes outgrow the caches:
//   RADIOSITY_BENCH_SCENE=builtin:rooms RADIOSITY_BENCH_PATCHES=1000000 RADIOSITY_BENCH_RAYS=8
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"

namespace radiosity::bench {

inline std::string fromEnvironment(const char* name, const char* otherwise) {
  const char* value = std::getenv(name);
  return value && *value ? value : otherwise;
}

inline const std::string kScene = fromEnvironment("RADIOSITY_BENCH_SCENE", "builtin:cornell");
inline const int64_t kPatches = std::stoll(fromEnvironment("RADIOSITY_BENCH_PATCHES", "5000"));
inline const int64_t kRaysPerPatch = std::stoll(fromEnvironment("RADIOSITY_BENCH_RAYS", "256"));

/// The scene refined to about kPatches patches in curve order and moved into its tracing frame,
/// as `solve` meshes it.
inline const Mesh& benchPatches() {
  static const Mesh patches = [] {
    Mesh mesh = partition::orderAlongCurve(partition::refineToCount(loadScene(kScene), kPatches));
    normaliseForTracing(mesh);
    return mesh;
  }();
  return patches;
}

/// The stage's tracer, built once for every run of the benchmarks (with the repetitions
/// interleaved, each run would otherwise build its BVH again: minutes at 10^7 patches).
inline const trace::SceneTracer& benchTracer() {
  static const trace::SceneTracer tracer(benchPatches());
  return tracer;
}

}  // namespace radiosity::bench
