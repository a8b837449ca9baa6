// Twins: a hash of each triangle's sorted positions, then an exact comparison where hashes
// repeat.
#include "trace/twins.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <tuple>

namespace radiosity::trace {

namespace {

bool lexicographicLess(Vec3 a, Vec3 b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); }

// The corners of triangle t in lexicographic order of their positions; false when two corners
// sit on the same position (such a triangle has no orientation and no twin).
bool sortedCorners(const Mesh& mesh, int64_t t, std::array<int, 3>& order) {
  order = {0, 1, 2};
  auto less = [&](int a, int b) { return lexicographicLess(mesh.corner(t, a), mesh.corner(t, b)); };
  if (less(order[1], order[0])) std::swap(order[0], order[1]);
  if (less(order[2], order[1])) std::swap(order[1], order[2]);
  if (less(order[1], order[0])) std::swap(order[0], order[1]);
  return less(order[0], order[1]) && less(order[1], order[2]);
}

// 1 when `order` is an odd permutation of (0, 1, 2). Two triangles on the same three positions
// have the same orientation exactly when their sorted corner orders have the same parity.
int parity(const std::array<int, 3>& order) {
  return ((order[0] > order[1]) + (order[0] > order[2]) + (order[1] > order[2])) & 1;
}

uint64_t mix(uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  return h ^ (h >> 31);
}

// A hash of the set of triangle t's positions (0: degenerate, never a twin).
uint64_t positionHash(const Mesh& mesh, int64_t t) {
  std::array<int, 3> order;
  if (!sortedCorners(mesh, t, order)) return 0;
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (int k : order) {
    const Vec3 p = mesh.corner(t, k);
    for (double c : {p.x, p.y, p.z}) {
      c += 0.0;  // -0 and +0 are the same coordinate
      uint64_t bits;
      std::memcpy(&bits, &c, sizeof bits);
      h = mix(h + bits);
    }
  }
  return h == 0 ? 1 : h;
}

}  // namespace

Twins findTwins(const Mesh& mesh) {
  const int64_t n = mesh.triangleCount();
  std::vector<uint64_t> repeated;
  {
    std::vector<uint64_t> hashes(n);
    for (int64_t t = 0; t < n; ++t) hashes[t] = positionHash(mesh, t);
    std::sort(hashes.begin(), hashes.end());
    for (int64_t i = 1; i < n; ++i) {
      if (hashes[i] != 0 && hashes[i] == hashes[i - 1] &&
          (repeated.empty() || repeated.back() != hashes[i])) {
        repeated.push_back(hashes[i]);
      }
    }
  }
  Twins twins;
  if (repeated.empty()) return twins;

  // The triangles whose hash repeats, ordered by hash, then exact sorted positions, then id.
  struct Candidate {
    uint64_t hash;
    int64_t triangle;
    std::array<int, 3> order;  ///< corners in lexicographic order of position
    Vec3 position(const Mesh& mesh, int k) const { return mesh.corner(triangle, order[k]); }
  };
  std::vector<Candidate> candidates;
  for (int64_t t = 0; t < n; ++t) {
    const uint64_t h = positionHash(mesh, t);
    if (h == 0 || !std::binary_search(repeated.begin(), repeated.end(), h)) continue;
    Candidate c{h, t, {}};
    sortedCorners(mesh, t, c.order);
    candidates.push_back(c);
  }
  // Strictly before in the order of places (equal places: the same three positions).
  auto placeLess = [&](const Candidate& a, const Candidate& b) {
    if (a.hash != b.hash) return a.hash < b.hash;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = a.position(mesh, k), q = b.position(mesh, k);
      if (lexicographicLess(p, q)) return true;
      if (lexicographicLess(q, p)) return false;
    }
    return false;
  };
  std::sort(candidates.begin(), candidates.end(), [&](const Candidate& a, const Candidate& b) {
    if (placeLess(a, b)) return true;
    if (placeLess(b, a)) return false;
    return a.triangle < b.triangle;
  });

  for (size_t first = 0; first < candidates.size();) {
    size_t end = first + 1;
    while (end < candidates.size() && !placeLess(candidates[first], candidates[end])) ++end;
    // The first (smallest id) of each orientation in the group [first, end).
    std::array<size_t, 2> firstOf = {end, end};
    for (size_t i = first; i < end; ++i) {
      const int side = parity(candidates[i].order);
      if (firstOf[side] == end) firstOf[side] = i;
    }
    if (firstOf[0] != end && firstOf[1] != end) {
      if (twins.twin.empty()) {
        twins.twin.assign(n, -1);
        twins.twinCorners.assign(n, 0);
      }
      for (size_t i = first; i < end; ++i) {
        const Candidate& c = candidates[i];
        const Candidate& other = candidates[firstOf[1 - parity(c.order)]];
        // The twin's corner other.order[k] sits on this triangle's corner c.order[k].
        std::array<int, 3> onTwin{};
        for (int k = 0; k < 3; ++k) onTwin[other.order[k]] = c.order[k];
        twins.twin[c.triangle] = other.triangle;
        twins.twinCorners[c.triangle] = static_cast<uint8_t>(onTwin[1] | onTwin[2] << 2);
        ++twins.count;
      }
    }
    first = end;
  }
  return twins;
}

}  // namespace radiosity::trace
