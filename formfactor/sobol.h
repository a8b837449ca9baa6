// An Owen-scrambled Sobol' sequence in four dimensions (two for the point on the patch, two for
// the direction). Sample k depends on k and the scramble seeds only, never on how many samples
// are drawn, so N samples and then M more are exactly the first N + M samples: rows can be
// refined later (restart with more rays) and stay stratified at every power of two.
//
// Scrambling: Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020 — the
// Laine–Karras hash applied to the bit-reversed value is a nested uniform (Owen) scramble, so
// each patch gets an independent, unbiased randomisation of the same well-distributed points.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

namespace radiosity::formfactor {

namespace sobol_detail {

// Generator matrices (as 32 direction numbers each) of the first four Sobol' dimensions, from
// the primitive polynomials and initial numbers of Joe & Kuo (new-joe-kuo-6.21201), built once.
struct Directions {
  uint32_t v[4][32];
  constexpr Directions() : v{} {
    // Dimension 0: van der Corput. Dimensions 1..3: (degree s, coefficients a, initial m).
    constexpr int degree[4] = {0, 1, 2, 3};
    constexpr uint32_t coefficients[4] = {0, 0, 1, 1};
    constexpr uint32_t initial[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 3, 0}, {1, 3, 1}};
    for (int i = 0; i < 32; ++i) v[0][i] = 1u << (31 - i);
    for (int d = 1; d < 4; ++d) {
      const int s = degree[d];
      uint32_t m[32] = {};
      for (int k = 0; k < s; ++k) m[k] = initial[d][k];
      for (int k = s; k < 32; ++k) {
        uint32_t next = m[k - s] ^ (m[k - s] << s);
        for (int j = 1; j < s; ++j) {
          if ((coefficients[d] >> (s - 1 - j)) & 1u) next ^= m[k - j] << j;
        }
        m[k] = next;
      }
      for (int k = 0; k < 32; ++k) v[d][k] = m[k] << (31 - k);
    }
  }
};

inline constexpr Directions kDirections{};

constexpr uint32_t reverseBits(uint32_t x) {
  x = __builtin_bswap32(x);  // bytes in reverse order; then the bits within each byte
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

}  // namespace sobol_detail

/// The unscrambled Sobol' value of sample `index` in `dimension` (0..3), as 32 fraction bits.
constexpr uint32_t sobolBits(uint32_t index, int dimension) {
  uint32_t x = 0;
  for (; index != 0; index &= index - 1) {  // one step per set bit
    x ^= sobol_detail::kDirections.v[dimension][std::countr_zero(index)];
  }
  return x;
}

/// Samples visit the Sobol' points in Gray-code order: sample s is point s ^ (s >> 1). Every
/// power-of-two prefix is the same point set as in index order, and consecutive samples differ
/// in one direction number (see SobolWalk).
constexpr uint32_t sobolPointOfSample(uint32_t sample) { return sample ^ (sample >> 1); }

namespace sobol_detail {
// The direction numbers bit-reversed: the XOR of reversed numbers is the reversed XOR, so a
// walk can keep its points in the bit order the scramble works in.
struct ReversedDirections {
  uint32_t v[4][32];
  constexpr ReversedDirections() : v{} {
    for (int d = 0; d < 4; ++d) {
      for (int k = 0; k < 32; ++k) v[d][k] = reverseBits(kDirections.v[d][k]);
    }
  }
};
inline constexpr ReversedDirections kReversedDirections{};
}  // namespace sobol_detail

/// Consecutive samples' points, scrambled: one XOR per dimension and step to move on, and
/// the points are kept bit-reversed so that the scramble needs one reversal, not two.
class SobolWalk {
 public:
  SobolWalk(uint32_t firstSample, const std::array<uint32_t, 4>& seeds)
      : sample_(firstSample), seeds_(seeds) {
    const uint32_t point = sobolPointOfSample(firstSample);
    for (int d = 0; d < 4; ++d) reversed_[d] = sobol_detail::reverseBits(sobolBits(point, d));
  }
  /// The current sample, scrambled, in [0, 1).
  std::array<double, 4> point() const {
    std::array<double, 4> u;
    for (int d = 0; d < 4; ++d) {
      const uint32_t scrambled =
          sobol_detail::reverseBits(sobol_detail::laineKarrasPermutation(reversed_[d], seeds_[d]));
      u[d] = scrambled * 0x1p-32;
    }
    return u;
  }
  void advance() {
    const int flipped = std::countr_zero(++sample_);
    for (int d = 0; d < 4; ++d) reversed_[d] ^= sobol_detail::kReversedDirections.v[d][flipped];
  }

 private:
  uint32_t sample_;
  std::array<uint32_t, 4> seeds_;
  std::array<uint32_t, 4> reversed_;
};

/// Nested uniform scramble of 32 fraction bits with `seed`.
constexpr uint32_t owenScramble(uint32_t bits, uint32_t seed) {
  using namespace sobol_detail;
  return reverseBits(laineKarrasPermutation(reverseBits(bits), seed));
}

/// Unscrambled bits scrambled with one seed per dimension, as numbers in [0, 1).
inline std::array<double, 4> scramble(const std::array<uint32_t, 4>& bits,
                                      const std::array<uint32_t, 4>& seeds) {
  std::array<double, 4> u;
  for (int d = 0; d < 4; ++d) u[d] = owenScramble(bits[d], seeds[d]) * 0x1p-32;
  return u;
}

/// Sample `sample` of the 4-D sequence scrambled with one seed per dimension, in [0, 1).
inline std::array<double, 4> scrambledSobol(uint32_t sample, const std::array<uint32_t, 4>& seeds) {
  const uint32_t point = sobolPointOfSample(sample);
  return scramble(
      {sobolBits(point, 0), sobolBits(point, 1), sobolBits(point, 2), sobolBits(point, 3)}, seeds);
}

}  // namespace radiosity::formfactor
