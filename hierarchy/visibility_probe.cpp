// Probe rays between node pairs (visibility_probe.h).
#include "hierarchy/visibility_probe.h"

#include "trace/random_streams.h"

namespace radiosity::hierarchy {

bool VisibilityProbe::seesWhole(const ClusterNode& receiver, const ClusterNode& source) {
  const uint64_t pair = static_cast<uint64_t>(receiver.begin) * 0x9E3779B97F4A7C15ULL ^
                        static_cast<uint64_t>(receiver.end) * 0xC2B2AE3D27D4EB4FULL ^
                        static_cast<uint64_t>(source.begin) * 0x165667B19E3779F9ULL ^
                        static_cast<uint64_t>(source.end);
  const uint64_t key = pair | 1;  // (never 0, the empty slot's mark)
  size_t slot = (key >> 20) & (kSlots - 1);
  for (; key_[slot] != 0; slot = (slot + 1) & (kSlots - 1))
    if (key_[slot] == key) return clear_[slot] != 0;
  const bool clear = probe(receiver, source, pair);
  ++probed_;
  if (2 * (used_ + 1) > kSlots) {  // half full: forget everything (answers do not change)
    std::fill(key_.begin(), key_.end(), 0);
    used_ = 0;
    slot = (key >> 20) & (kSlots - 1);
  }
  key_[slot] = key;
  clear_[slot] = clear;
  ++used_;
  return clear;
}

// Whether every probe ray between the pair is unblocked.
bool VisibilityProbe::probe(const ClusterNode& receiver, const ClusterNode& source,
                            uint64_t key) const {
  for (int k = 0; k < rays_; ++k) {
    const Vec3 from = pointOn(receiver, key, 2 * k), to = pointOn(source, key, 2 * k + 1);
    const Vec3 along = to - from;
    const double distance = length(along);
    if (distance <= 0) continue;
    const auto hit = tracer_.intersect(from, (1.0 / distance) * along, 1e-6, distance - 1e-6);
    if (hit && !receiver.holds(hit->patch) && !source.holds(hit->patch)) return false;
  }
  return true;
}

// A point of one of `node`'s patches (its k-th probe end), lifted off it by 1e-6 along its normal
// (the tracing frame's scale: normaliseForTracing).
Vec3 VisibilityProbe::pointOn(const ClusterNode& node, uint64_t key, int k) const {
  trace::HashStream stream = trace::kHierarchyProbe;
  stream.salt += static_cast<uint32_t>(k);
  const uint64_t h = trace::streamHash(0, key, stream);
  const int64_t patch = node.begin + static_cast<int64_t>(h % static_cast<uint64_t>(node.size()));
  double u = static_cast<double>((h >> 11) & 0xFFFFF) / 1048576.0;
  double v = static_cast<double>((h >> 31) & 0xFFFFF) / 1048576.0;
  if (u + v > 1) u = 1 - u, v = 1 - v;
  const Vec3 a = patches_.corner(patch, 0), b = patches_.corner(patch, 1),
             c = patches_.corner(patch, 2);
  return a + u * (b - a) + v * (c - a) + 1e-6 * patches_.normal(patch);
}

}  // namespace radiosity::hierarchy
