// Patches that see nothing: the floor under a block standing on it (once the floor is cut along
// the block's walls), a face inside a closed solid. Every ray from such a patch meets the back of
// a face, so nothing reaches it and nothing it reflects goes anywhere.
#include <cstdint>
#include <vector>

#include "formfactor/formfactor.h"
#include "formfactor/hemisphere_rays.h"

namespace radiosity::formfactor {

namespace {

// The probe has a scramble of its own and a fixed seed (trace/random_streams.h): which patches
// are hidden is a property of the mesh, not of the run's --seed, and its rays are independent of
// the rows'.
// A few rays decide almost every patch (the first that meets a front or leaves the scene); a
// patch is hidden only when all of the first kProbeRays meet backs. The points are stratified
// over the whole patch, so a patch that reaches out from under a block by a share of its area
// well above 1/kProbeRays is seen to.
constexpr int64_t kFirstRays = 4;
constexpr int64_t kProbeRays = 64;

bool allBacks(const SceneTracer::HitBatch& hits, size_t count) {
  for (size_t k = 0; k < count; ++k)
    if (hits.patch[k] < 0 || hits.front[k]) return false;
  return true;
}

}  // namespace

std::vector<uint8_t> hiddenPatches(const SceneTracer& tracer, const Mesh& patches,
                                   int64_t firstPatch, int64_t endPatch) {
  std::vector<uint8_t> hidden(endPatch - firstPatch, 0);
  SceneTracer::RayBatch rays;
  SceneTracer::HitBatch hits;
  std::vector<uint32_t> scratch;
  for (int64_t p = firstPatch; p < endPatch; ++p) {
    const double offset = rayOffset(tracer, p);
    makeHemisphereRays(
        patches, {p, 0, kFirstRays, trace::kHiddenProbeSeed, offset, trace::kHiddenProbeScramble},
        rays, scratch);
    tracer.intersect(rays, hits);
    if (!allBacks(hits, rays.size())) continue;
    makeHemisphereRays(patches,
                       {p, kFirstRays, kProbeRays - kFirstRays, trace::kHiddenProbeSeed, offset,
                        trace::kHiddenProbeScramble},
                       rays, scratch);
    tracer.intersect(rays, hits);
    hidden[p - firstPatch] = allBacks(hits, rays.size()) ? 1 : 0;
  }
  return hidden;
}

}  // namespace radiosity::formfactor
