// Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as 1, 2, 3", SC'11): a
// counter-based generator. The numbers for (seed, patch, sample) are a pure function of those
// keys, so a form-factor row is the same on any rank, in any order, after any restart.
#pragma once

#include <array>
#include <cstdint>

namespace radiosity::trace {

/// Philox's key for a seed: its two halves.
inline std::array<uint32_t, 2> philoxKey(uint64_t seed) {
  return {static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32)};
}

inline std::array<uint32_t, 4> philox4x32(std::array<uint32_t, 4> counter,
                                          std::array<uint32_t, 2> key) {
  constexpr uint32_t kMul0 = 0xD2511F53u, kMul1 = 0xCD9E8D57u;
  constexpr uint32_t kWeyl0 = 0x9E3779B9u, kWeyl1 = 0xBB67AE85u;
  for (int round = 0; round < 10; ++round) {
    uint64_t p0 = uint64_t{kMul0} * counter[0];
    uint64_t p1 = uint64_t{kMul1} * counter[2];
    counter = {static_cast<uint32_t>(p1 >> 32) ^ counter[1] ^ key[0], static_cast<uint32_t>(p1),
               static_cast<uint32_t>(p0 >> 32) ^ counter[3] ^ key[1], static_cast<uint32_t>(p0)};
    key = {key[0] + kWeyl0, key[1] + kWeyl1};
  }
  return counter;
}

/// Four uniform numbers in [0, 1) for one (seed, patch, sample, stream).
inline std::array<double, 4> uniforms(uint64_t seed, uint64_t patch, uint32_t sample,
                                      uint32_t stream) {
  auto bits =
      philox4x32({sample, stream, static_cast<uint32_t>(patch), static_cast<uint32_t>(patch >> 32)},
                 philoxKey(seed));
  std::array<double, 4> u;
  for (int k = 0; k < 4; ++k) u[k] = bits[k] * 0x1p-32;
  return u;
}

}  // namespace radiosity::trace
