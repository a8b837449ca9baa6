// How --balance cuts the ranks' blocks of patches (run/rank_balance.h), and its names.
#pragma once

#include "core/enum_names.h"

namespace radiosity::run {

/// kAuto: by cost from kCostBalancedRanks ranks up (run/rank_balance.h), by count below.
enum class BalanceMode { kAuto, kCost, kCount };

/// The modes' names on the command line and in the options line, in the order --help lists.
inline constexpr NamedValue<BalanceMode> kBalanceModes[] = {
    {BalanceMode::kAuto, "auto"},
    {BalanceMode::kCost, "cost"},
    {BalanceMode::kCount, "count"},
};

/// "auto", "cost" or "count".
inline const char* balanceModeName(BalanceMode mode) { return nameIn(kBalanceModes, mode); }

}  // namespace radiosity::run
