// Private to formfactor/: making the hemisphere rays of a patch, shared by the row sampler
// and the public hemisphereRays().
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "formfactor/formfactor.h"
#include "trace/random_streams.h"

namespace radiosity::formfactor {

/// Scramble seeds of one (seed, patch) for a stream (trace/random_streams.h: the hemisphere
/// sample, the emitter sample, a pilot's, the hidden-patch probe's).
std::array<uint32_t, 4> scrambleSeeds(uint64_t seed, int64_t patch, uint32_t stream);

/// Which hemisphere samples of a patch to make: [firstSample, firstSample + count) of `patch`'s
/// sequence scrambled by (seed, patch, `stream`: trace::kHemisphereScramble for the rows), the
/// rays' origins `offset` off the patch.
struct HemisphereSamples {
  int64_t patch = 0;
  int64_t firstSample = 0;
  int64_t count = 0;
  uint64_t seed = 0;
  double offset = 0;
  uint32_t stream = trace::kHemisphereScramble;
};

/// The `samples` of a patch of `patches` as rays into `rays` (resized); `scratch` is reused
/// memory.
void makeHemisphereRays(const Mesh& patches, const HemisphereSamples& samples,
                        SceneTracer::RayBatch& rays, std::vector<uint32_t>& scratch);

}  // namespace radiosity::formfactor
