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

/// Samples [firstSample, firstSample + count) of `patch` as rays into `rays` (resized);
/// `scratch` is reused memory; `stream` picks the scramble (trace::kHemisphereScramble for the
/// rows).
void makeHemisphereRays(const Mesh& patches, int64_t patch, int64_t firstSample, int64_t count,
                        uint64_t seed, double offset, SceneTracer::RayBatch& rays,
                        std::vector<uint32_t>& scratch,
                        uint32_t stream = trace::kHemisphereScramble);

}  // namespace radiosity::formfactor
