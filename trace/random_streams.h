// The run's random streams, named in one place. Every random choice is Philox4x32-10
// (counter_rng.h) keyed by the user's --seed: a pure function of (seed, purpose, patch, sample),
// so a row is the same on any rank, in any order, after any restart. Each purpose has its own
// stream below, with the counter layout it has always had, so that results stay bit for bit
// those of earlier versions.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "trace/counter_rng.h"

namespace radiosity::trace {

/// The per-patch Sobol' scrambles (formfactor/hemisphere_rays): the third counter word.
enum ScrambleStream : uint32_t {
  kHemisphereScramble = 0,       ///< a row's hemisphere samples (point, direction)
  kEmitterScramble = 1,          ///< a row's emitter samples (which emitter, point on it)
  kPilotHemisphereScramble = 2,  ///< a light-choice pilot's (formfactor/light_choice.h)
  kPilotEmitterScramble = 3,
  kHiddenProbeScramble = 4,  ///< the hidden-patch probe's (formfactor/hidden_patches.cpp)
};

/// The hidden-patch probe's seed: fixed, as whether a patch is hidden is geometry, not chance.
inline constexpr uint64_t kHiddenProbeSeed = 0;

/// The rank-balance pilot's seed (run/rank_balance.cpp): its rows are not the run's rows.
inline uint64_t pilotSeed(uint64_t seed) { return seed + 0x70110f5eedULL; }

/// Streams hashed per value (a patch id, a replica number): the counter (value's halves, tag,
/// salt).
struct HashStream {
  uint32_t tag, salt;
};
inline constexpr HashStream kVerifySample{0x76657269u /* "veri" */, 0};
inline constexpr HashStream kCalibrationSample{1, 0x5ca1ab1eu};
inline constexpr HashStream kCalibrationReplicaSeed{2, 0x5ca1ab1eu};
/// The hierarchy's visibility probes between two nodes (hierarchy/visibility_probe.h): the value is
/// the pair's key, the salt the probe's end.
inline constexpr HashStream kHierarchyProbe{3, 0x9b0be5u};

/// 64 bits of stream `stream` at `value`: Philox's first two words.
inline uint64_t streamHash(uint64_t seed, uint64_t value, HashStream stream) {
  const auto bits = philox4x32(
      {static_cast<uint32_t>(value), static_cast<uint32_t>(value >> 32), stream.tag, stream.salt},
      philoxKey(seed));
  return (uint64_t{bits[0]} << 32) | bits[1];
}

/// A patch's sort key in a random sample that takes lit patches (B > 0) first: the hash with
/// its top bit marking the unlit, so that they sort after every lit one.
inline uint64_t sampleKey(uint64_t hash, bool lit) {
  return (hash >> 1) | (lit ? 0 : uint64_t{1} << 63);
}

/// A sample: the `count` smallest (key, id) pairs, smallest first (ties by id).
using KeyedIds = std::vector<std::pair<uint64_t, int64_t>>;
inline KeyedIds smallestKeys(KeyedIds keyed, int64_t count) {
  const auto keep = std::min<int64_t>(count, static_cast<int64_t>(keyed.size()));
  std::partial_sort(keyed.begin(), keyed.begin() + keep, keyed.end());
  keyed.resize(static_cast<size_t>(keep));
  return keyed;
}

/// A sample's ids, in ascending order.
inline std::vector<int64_t> idsOf(const KeyedIds& sample) {
  std::vector<int64_t> ids;
  for (const auto& [key, id] : sample) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace radiosity::trace
