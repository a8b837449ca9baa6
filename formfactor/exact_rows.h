// Private to formfactor/: rows of F without rays, for scenes where every pair of patches that
// face each other sees each other whole (formfactor.h, chooseRows): each F_ij by
// triangleToTriangleFactor, written as the sums of a tally in which every sample scored F_ij.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh.h"
#include "formfactor/polygon_factors.h"

namespace radiosity::formfactor {

/// How far from 1 the share of a point's hemisphere covered may be for the patches to count as
/// closing it: round-off of a sum over the row, far below any opening's share.
inline constexpr double kClosedSlack = 1e-9;

class ExactRows {
 public:
  /// `onFloats`: every F_ij is rounded to a multiple of 2^-32 that a float holds exactly, for a
  /// store of floats (SplitRows::singlePrecision), the row's sum kept all the same.
  /// `pairsOnce`: each row keeps the pairs it owns (ownsPair) and, as its diagonal entry, the
  /// sum of the others (SplitRows::pairsOnce).
  explicit ExactRows(const Mesh& patches, bool onFloats = false, bool pairsOnce = false);

  /// Row i over `samples` samples, appended as (ascending columns, fixed-point sums): each
  /// F_ij rounded to a multiple of 2^-32, times `samples`, so that the rows extend and merge
  /// like sampled ones; the units add up to the row's sum rounded (1 in a closed scene), but
  /// for a row on floats without entries small enough to take the rounding (roundToUnits).
  struct Appended {
    int64_t pairFactors = 0;  ///< computed: the patches i faces
    bool offItsSum = false;   ///< the units do not add up to the row's sum
  };
  Appended appendRow(int64_t i, int64_t samples, std::vector<int64_t>& columns,
                     std::vector<int64_t>& sums) const;

 private:
  std::vector<PatchShape> shapes_;
  TriangleTable table_;  ///< the same triangles, for threePointFactors
  double slack_;         ///< "on the plane" within this (a length)
  bool onFloats_;
  bool pairsOnce_;
};

/// Whole units of 2^-32 for values given in those units (`exact`, each ≥ 0), adding up to
/// `total`: each floored and the units left handed out one each, largest remainder first (ties
/// by position). `onFloats`: values of 2^24 units or more (2^-8 and up) are rounded to the 24
/// significant bits of a float instead, and the units left or taken go to the others (below
/// 2^23 units: there a float holds every whole unit), more than one each where they must; should
/// none be below, the row keeps what the rounding left over (less than 2^-24 of its sum).
std::vector<int64_t> roundToUnits(const std::vector<double>& exact, int64_t total, bool onFloats);

/// A length below which two points of the mesh count as one for plane tests: 1e-9 of its
/// bounding box's diagonal.
double planeSlack(const Mesh& patches);

}  // namespace radiosity::formfactor
