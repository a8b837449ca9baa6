// Private to formfactor/: making the hemisphere rays of a patch, shared by the row sampler
// and the public hemisphereRays().
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

// Scramble seeds of one (seed, patch): one set for the hemisphere sample (point, direction),
// one for the emitter sample (which emitter, point on it).
inline constexpr uint32_t kHemisphereScramble = 0;
inline constexpr uint32_t kEmitterScramble = 1;
// And of a cluster's pilot (formfactor/light_choice.h), drawn from its patches apart from the rows.
inline constexpr uint32_t kPilotHemisphereScramble = 2;
inline constexpr uint32_t kPilotEmitterScramble = 3;

std::array<uint32_t, 4> scrambleSeeds(uint64_t seed, int64_t patch, uint32_t stream);

/// Samples [firstSample, firstSample + count) of `patch` as rays into `rays` (resized);
/// `scratch` is reused memory; `stream` picks the scramble (kHemisphereScramble for the rows).
void makeHemisphereRays(const Mesh& patches, int64_t patch, int64_t firstSample, int64_t count,
                        uint64_t seed, double offset, SceneTracer::RayBatch& rays,
                        std::vector<uint32_t>& scratch, uint32_t stream = kHemisphereScramble);

}  // namespace radiosity::formfactor
