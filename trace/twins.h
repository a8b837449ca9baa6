// Private to formfactor/: twins, coincident triangles of opposite orientation (the two faces of
// a thin two-sided surface where they are triangulated alike), found once when SceneTracer is
// built, so that a hit on the back of one is the front of the other at the cost of a look-up.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace radiosity::trace {

struct Twins {
  std::vector<int64_t> twin;         ///< per triangle its twin or -1; empty when none has one
  std::vector<uint8_t> twinCorners;  ///< corner of t on the twin's corner 1 | corner 2 << 2
  int64_t count = 0;                 ///< triangles with a twin
};

/// The twins of every triangle: same three positions (exactly, shared vertex indices or not),
/// opposite orientation; of several, the one with the smallest id. Costs a hash per triangle
/// and one sort of the hashes (8 bytes per triangle, freed on return); only triangles whose hash
/// repeats are looked at further, so a scene without coincident triangles pays nothing else.
Twins findTwins(const Mesh& mesh);

/// The barycentric coordinates of a hit on a triangle carried over to its twin, whose corners
/// 1 and 2 sit on the triangle's corners `twinCorners & 3` and `twinCorners >> 2`.
template <typename Real>
void twinBarycentrics(uint8_t twinCorners, Real& u, Real& v) {
  const Real weight[3] = {1 - u - v, u, v};
  u = weight[twinCorners & 3];
  v = weight[(twinCorners >> 2) & 3];
}

}  // namespace radiosity::trace
