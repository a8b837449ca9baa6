// Which colour channels need a solve of their own: the work a scene does not need is left out.
// Private to solve/.
#pragma once

#include <mpi.h>

#include <array>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "formfactor/formfactor.h"

namespace radiosity::solve {

struct ChannelPlan {
  std::array<bool, 3> noReflection{};     ///< ρ_c = 0 on every patch: B_c = E_c, no solve
  std::array<int, 3> sameAs{-1, -1, -1};  ///< same ρ and E as this earlier channel: copy it
  /// ρ_c = 1 on every patch of a closed scene (every row of F sums to 1): I − F is singular.
  std::array<bool, 3> singular{};
  /// Patches with ρ_c = 0 in a channel that is solved: B = E there, outside the iteration.
  std::array<int64_t, 3> blackPatches{};

  bool needsSolve(int c) const { return !noReflection[c] && sameAs[c] < 0; }
  /// What was left out, for the log and the result's `left_out` attribute ("none" if nothing),
  /// in a result of `channels` channels (1: the other two are its copies, not said), of whose
  /// black patches `hidden` are hidden ones.
  std::string leftOut(int channels = 3, int64_t hidden = 0) const;
};

/// Collective on `comm`; every rank gets the same plan.
/// `rowSums`: this rank's Σ_j F_ij (formfactor::rowSums).
ChannelPlan planChannels(MPI_Comm comm, const std::vector<double>& rowSums,
                         const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission);

}  // namespace radiosity::solve
