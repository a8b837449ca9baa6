#include "jobs/verify_pilot.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>

#include "run/duration.h"

namespace radiosity::jobs {

namespace {

/// The pilot, on rank 0 and one thread: a few paths on a few of the sampled
/// patches (at most 64 paths on 8 patches, and at most half a second once one pair is done),
/// for the mean length of a path and the time it takes. Its own random numbers, so the
/// reference is the same with or without it. Bounded: a path has at most --max-bounces.
struct Pilot {
  int64_t paths = 0, bounces = 0, capped = 0;
  double seconds = 0;
};

Pilot runPilot(const verify::PathTracer& tracer, const std::vector<int64_t>& chosen,
               uint64_t seed) {
  constexpr size_t kPatches = 8;
  constexpr int64_t kMostPaths = 64;
  constexpr double kMostSeconds = 0.5;
  constexpr uint64_t kPilotSalt = 0x70696c6f74000000ull;  // "pilot"
  Pilot pilot;
  const double start = MPI_Wtime();
  const size_t patches = std::min(chosen.size(), kPatches);
  for (uint64_t round = 0;
       pilot.paths < kMostPaths && (round == 0 || MPI_Wtime() - start < kMostSeconds); ++round) {
    const verify::PatchReference traced =
        tracer.trace(chosen[round % patches], 2, seed ^ (kPilotSalt + round));
    pilot.paths += traced.paths;
    pilot.bounces += traced.bounces;
    pilot.capped += traced.capped;
  }
  pilot.seconds = MPI_Wtime() - start;
  return pilot;
}

std::string number(double x, const char* format) {
  char text[48];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

}  // namespace

void reportPilot(const run::Console& console, const verify::PathTracer& tracer,
                 const std::vector<int64_t>& chosen, const VerifySettings& settings) {
  // Up front, how long it will take, and whether paths end at all (ρ = 1 in a closed
  // region: only at the cap), so that a run that would not end in reasonable time says so.
  const Pilot pilot = runPilot(tracer, chosen, settings.seed);
  const double meanBounces = static_cast<double>(pilot.bounces) / static_cast<double>(pilot.paths);
  const double predicted = pilot.seconds / static_cast<double>(pilot.paths) *
                           static_cast<double>(chosen.size()) *
                           static_cast<double>(settings.paths) /
                           (static_cast<double>(console.ranks()) * settings.threads);
  const std::string shorten = "fewer --patches or --paths, or more ranks or --threads";
  console.info("  pilot: " + std::to_string(pilot.paths) + " paths, mean " +
               number(meanBounces, "%.3g") + " bounces; path tracing should take about " +
               run::describeDuration(predicted));
  if (pilot.capped > 0 || meanBounces >= 0.5 * static_cast<double>(settings.maxBounces))
    console.warn("verify: paths in this scene hardly end (reflectance near 1): mean " +
                 number(meanBounces, "%.3g") + " bounces, " + std::to_string(pilot.capped) +
                 " of " + std::to_string(pilot.paths) + " pilot paths cut at --max-bounces " +
                 std::to_string(settings.maxBounces) +
                 "; the reference misses the light beyond the cap, so it reads low; about " +
                 run::describeDuration(predicted) + " of path tracing" +
                 (predicted > 600 ? ": " + shorten + ", or a lower --max-bounces shorten it" : ""));
  else if (predicted > 600)
    console.warn("verify: path tracing should take about " + run::describeDuration(predicted) +
                 " (mean path " + number(meanBounces, "%.3g") + " bounces): " + shorten +
                 " shorten it");
}

}  // namespace radiosity::jobs
