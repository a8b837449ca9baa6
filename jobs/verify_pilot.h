// `verify`'s pilot: before the reference, how long it will take and whether paths end at all
// (reflectance near 1 in a closed region: only at --max-bounces), said up front so that a run
// that would not end in reasonable time says so.
#pragma once

#include <cstdint>
#include <vector>

#include "jobs/commands.h"
#include "run/console.h"
#include "verify/path_tracer.h"

namespace radiosity::jobs {

/// Traces a few paths on a few of the `chosen` patches (at most 64 paths on 8 patches, at most
/// half a second once one pair is done; its own random numbers, so the reference is the same
/// with or without it) and prints the mean path length and the predicted time, with a warning
/// when paths hardly end or the run would take over 10 minutes. Rank 0 alone.
void reportPilot(const run::Console& console, const verify::PathTracer& tracer,
                 const std::vector<int64_t>& chosen, const VerifySettings& settings);

}  // namespace radiosity::jobs
