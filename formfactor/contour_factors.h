// Private to formfactor/: view factors between triangles near each other by Stokes' theorem, the
// area integrals turned into ones around their edges (Sparrow's contour integral), the inner of
// those in closed form and the outer by adaptive Gauss-Legendre. Used where the triangles are
// within i's size of each other: there Lambert's closed form integrated over i varies over the
// distance between them, which may be thousands of times less than i (nearly touching plates),
// and a rule over i's area needs millions of points; along an edge it needs a few hundred.
#pragma once

#include "formfactor/polygon_factors.h"

namespace radiosity::formfactor {

/// A_i F_ij from the edges of i and of j: (1/2π) Σ over pairs of edges of ∫∫ ln r ds·dt, j on or
/// in front of i's plane, i on or in front of j's, nothing between them. Lengths are taken in
/// units of the pair's size, so that the sums cancel as little as they can.
struct ContourFactor {
  double value;  ///< F_ij
  double error;  ///< an estimate of |value − F_ij|: the quadrature's, summed over its pieces
};
ContourFactor contourFactor(const PatchShape& i, const PatchShape& j);

/// The tolerance on F_ij the quadrature is run to (absolute: the terms it sums are of the order
/// of the pair's size squared, whatever F_ij), and the halvings of an edge it may take.
inline constexpr double kContourTolerance = 1e-11;
inline constexpr int kContourMaxDepth = 48;

}  // namespace radiosity::formfactor
