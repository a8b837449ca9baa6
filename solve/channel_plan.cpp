// Which colour channels need a solve of their own, and what the scene lets us leave out.
#include "solve/channel_plan.h"

#include <algorithm>
#include <cmath>

#include "core/channels.h"

namespace radiosity::solve {

namespace {

// True on every rank when `local` is true on every rank.
bool everywhere(MPI_Comm comm, bool local) {
  int mine = local ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm);
  return all == 1;
}

}  // namespace

std::string ChannelPlan::leftOut(int channels, int64_t hidden) const {
  std::string text;
  for (int c = 0; c < channels; ++c) {
    std::string what;
    const int64_t black = blackPatches[c] - std::min(hidden, blackPatches[c]);
    if (noReflection[c]) {
      what = "no reflection, B = E";
    } else if (sameAs[c] >= 0) {
      what = std::string("same reflectance and emission as ") + kChannelNames[sameAs[c]];
    } else if (blackPatches[c] > 0) {
      if (black > 0) what = std::to_string(black) + " black patches (rho = 0)";
      if (hidden > 0)
        what += (what.empty() ? "" : " and ") + std::to_string(hidden) +
                " hidden patches (nothing reaches them)";
      what += " outside the iteration";
    } else {
      continue;
    }
    // (one channel: nothing to name)
    text += (text.empty() ? "" : "; ") +
            (channels == 1 ? std::string() : std::string(kChannelNames[c]) + ": ") + what;
  }
  return text.empty() ? "none" : text;
}

ChannelPlan planChannels(MPI_Comm comm, const std::vector<double>& rowSums,
                         const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission) {
  ChannelPlan plan;
  // A closed scene: every row of F sums to 1 (to round-off).
  bool closed = true;
  for (double sum : rowSums) closed = closed && std::abs(sum - 1) < 1e-9;
  closed = everywhere(comm, closed);

  for (int c = 0; c < 3; ++c) {
    bool black = true, white = true;
    int64_t blackCount = 0;
    for (const Rgb& rho : reflectance) {
      black = black && rho[c] == 0;
      white = white && rho[c] == 1;
      blackCount += rho[c] == 0 ? 1 : 0;
    }
    MPI_Allreduce(MPI_IN_PLACE, &blackCount, 1, MPI_INT64_T, MPI_SUM, comm);
    plan.noReflection[c] = everywhere(comm, black);
    plan.singular[c] = closed && everywhere(comm, white);
    for (int earlier = 0; earlier < c && plan.sameAs[c] < 0; ++earlier) {
      if (plan.sameAs[earlier] >= 0) continue;  // compare with the channel actually computed
      bool same = true;
      for (size_t i = 0; i < reflectance.size() && same; ++i) {
        same =
            reflectance[i][c] == reflectance[i][earlier] && emission[i][c] == emission[i][earlier];
      }
      if (everywhere(comm, same)) plan.sameAs[c] = earlier;
    }
    if (plan.noReflection[c]) plan.sameAs[c] = -1;  // nothing to copy: B = E is cheaper
    if (plan.needsSolve(c)) plan.blackPatches[c] = blackCount;
  }
  return plan;
}

}  // namespace radiosity::solve
