// The three colour channels every stage solves, reports and stores, in their one order.
#pragma once

#include <array>

namespace radiosity {

/// Channel c of an Rgb is kChannelNames[c].
inline constexpr std::array<const char*, 3> kChannelNames = {"red", "green", "blue"};

/// Channel c's name in a result of `channels` channels: a thermal (one-channel) result's one
/// channel is "grey"; reports, CSV and JSON name it so.
inline const char* channelName(int c, int channels) {
  return channels == 1 ? "grey" : kChannelNames[c];
}

/// The luminance of a colour, Y = Σ_c kLuminanceWeights[c] · rgb[c] (Rec. 709's): what the
/// renderer's exposure and the viewers' one-number picture (/display/luminance_tonemapped) see.
inline constexpr std::array<double, 3> kLuminanceWeights = {0.2126, 0.7152, 0.0722};
template <class Rgb>
constexpr double luminance(const Rgb& rgb) {
  return kLuminanceWeights[0] * rgb[0] + kLuminanceWeights[1] * rgb[1] +
         kLuminanceWeights[2] * rgb[2];
}

}  // namespace radiosity
