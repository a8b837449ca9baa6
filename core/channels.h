// The three colour channels every stage solves, reports and stores, in their one order.
#pragma once

#include <array>

namespace radiosity {

/// Channel c of an Rgb is kChannelNames[c].
inline constexpr std::array<const char*, 3> kChannelNames = {"red", "green", "blue"};

}  // namespace radiosity
