// The one error measure of the project: the error of the light the solver computes, as a user
// reads it. Per channel, the area-weighted RMS of each patch's error relative to its own value,
// over the patches that reflect in that channel (ρ_c > 0: where the solver computes anything;
// an emitter's own E dominates any norm that includes it and says nothing about the light
// computed), with a floor of 1 % of the area-weighted mean value for near-black patches, so
// that a patch at B ≈ 0 does not turn a tiny absolute error into an infinite relative one.
// Patches no light reaches (value and error exactly 0: the ground around a closed room, a
// face turned away from every lamp) are left out: there is no light there to be wrong, and a
// ground of 10^6 m² counted at zero error would hide the error of the room standing on it.
// Used for the estimated sampling error (log, result attributes, --target-error), the measured
// error of `study` and of `verify`, and docs/accuracy.md.
#pragma once

#include <mpi.h>

#include <array>
#include <vector>

#include "core/vec3.h"

namespace radiosity {

/// The floor below which a patch's value does not count smaller: this share of the mean.
inline constexpr double kLightErrorFloorShare = 0.01;

/// Per channel: the area-weighted mean of `value` over the patches with reflectance > 0 in that
/// channel and a value other than 0 (0 where there are none). Collective on `comm`; every vector
/// holds this rank's rows.
std::array<double, 3> reflectingMean(MPI_Comm comm, const std::vector<double>& area,
                                     const std::vector<Rgb>& reflectance,
                                     const std::vector<Rgb>& value);

/// Per channel: sqrt(Σ A_i (error_i / max(value_i, floor))² / Σ A_i) over the patches with
/// reflectance > 0 in that channel, but those whose value and error are both 0, floor =
/// kLightErrorFloorShare × reflectingMean(value); 0 for a channel where no patch reflects. `error`
/// holds absolute errors (or standard errors), `value` the values they are relative to (the
/// reference where there is one). Collective on `comm`; every vector holds this rank's rows.
std::array<double, 3> relativeLightError(MPI_Comm comm, const std::vector<double>& area,
                                         const std::vector<Rgb>& reflectance,
                                         const std::vector<Rgb>& value,
                                         const std::vector<Rgb>& error);

/// The patch's error relative to its value with the floor of relativeLightError().
inline double relativeToFloor(double error, double value, double floor) {
  const double denominator = value > floor ? value : floor;
  return denominator > 0 ? error / denominator : 0.0;
}

}  // namespace radiosity
