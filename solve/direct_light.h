// Private to solve/: the direct light inside each of a rank's rows, from its own shadow rays,
// which the discretisation estimate reconstructs H's direct part from (a shadow edge inside a
// patch shows in its slope).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/vec3.h"
#include "partition/partition.h"
#include "trace/trace.h"

namespace radiosity::solve {

/// Of the owned rows' direct light, what the slopes need: every row's mean, and the slope of the
/// rows a shadow edge crosses (elsewhere it is not used), in row order.
struct DirectParts {
  std::vector<Rgb> mean;
  std::vector<std::pair<int64_t, std::array<Vec3, 3>>> edgeSlope;  ///< (row, slope)
};

/// `samples` points stratified over each owned patch, each with one shadow ray to a point drawn
/// uniform over the emitters' area: H_direct(x) ≈ E_j cosθ_x cosθ_j A_emitters / (π r²) if
/// unseen. On `threads` threads; the same on any number of them (random numbers keyed by seed,
/// patch and sample).
DirectParts directLight(const trace::SceneTracer& tracer, const Mesh& patches,
                        partition::PatchRange owned, uint64_t seed, int64_t samples, int threads);

}  // namespace radiosity::solve
