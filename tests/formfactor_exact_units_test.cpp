// Exact rows' units of 2^-32 (formfactor::roundToUnits): on doubles each value floored and the
// units left handed to the largest remainders, as a full sort hands them out; on floats the
// large values rounded to a float and the rest made up by the small ones, taken as well as given,
// several each where they must, and what cannot be made up where none is small.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "formfactor/exact_rows.h"

namespace radiosity::formfactor {
namespace {

// Whether a float holds units · 2^-32 exactly.
bool floatHolds(int64_t units) {
  const double value = std::ldexp(static_cast<double>(units), -32);
  return static_cast<double>(static_cast<float>(value)) == value;
}

int64_t total(const std::vector<int64_t>& units) {
  int64_t sum = 0;
  for (int64_t u : units) sum += u;
  return sum;
}

// A row as a closed row comes: a few entries of 2^-8 and more (where a float's grid is coarser
// than 2^-32) among many small ones, 1 in all; in units of 2^-32, none of them whole.
std::vector<double> closedRowInUnits() {
  std::vector<double> row = {0.21, 0.13, 0.07, 0.011, 0.0042};
  double left = 1;
  for (double v : row) left -= v;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> share(0.5, 1.5);
  std::vector<double> small(2000);
  double smallSum = 0;
  for (double& v : small) smallSum += v = share(random);
  for (double v : small) row.push_back(v * left / smallSum);
  for (double& v : row) v *= 0x1p32;
  return row;
}

TEST(ExactRows, UnitsAddUpToTheRowsSumOnDoublesAndOnFloats) {
  const std::vector<double> exact = closedRowInUnits();
  const int64_t whole = int64_t{1} << 32;
  const std::vector<int64_t> onDoubles = roundToUnits(exact, whole, false);
  EXPECT_EQ(total(onDoubles), whole);
  for (size_t k = 0; k < exact.size(); ++k) EXPECT_LT(std::abs(onDoubles[k] - exact[k]), 1.0);
  const std::vector<int64_t> onFloats = roundToUnits(exact, whole, true);
  EXPECT_EQ(total(onFloats), whole);
  for (size_t k = 0; k < exact.size(); ++k) {
    EXPECT_TRUE(floatHolds(onFloats[k])) << k << ": " << onFloats[k];
    // The large ones a float's rounding (half its grid), the small ones within two units.
    EXPECT_LE(std::abs(onFloats[k] - exact[k]), std::max(2.0, exact[k] * 0x1p-24)) << k;
  }
  EXPECT_NE(onFloats, onDoubles);  // (the large entries moved onto the float grid)
}

// The units left go to the largest remainders, ties to the first entries: against a full sort,
// with remainders drawn from few values (many ties, many in one bucket of the selection) and
// from many, giving more or fewer units.
TEST(ExactRows, UnitsGoToTheLargestRemaindersAsAFullSortGivesThem) {
  std::mt19937_64 random(3);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 1 + static_cast<int>(random() % 3000);
    const int levels = trial % 2 == 0 ? 5 : 1 << 20;
    std::vector<double> exact(static_cast<size_t>(n));
    int64_t floors = 0;
    for (double& v : exact) {
      const auto whole = static_cast<int64_t>(random() % 100000);
      v = static_cast<double>(whole) + static_cast<double>(random() % levels) / levels;
      floors += whole;
    }
    const auto left = static_cast<int64_t>(random() % static_cast<uint64_t>(n + 1));
    std::vector<size_t> order(exact.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      const double ra = exact[a] - std::floor(exact[a]), rb = exact[b] - std::floor(exact[b]);
      return ra > rb || (ra == rb && a < b);
    });
    std::vector<int64_t> expected(exact.size());
    for (size_t k = 0; k < exact.size(); ++k)
      expected[k] = static_cast<int64_t>(std::floor(exact[k]));
    for (int64_t k = 0; k < left; ++k) ++expected[order[static_cast<size_t>(k)]];
    EXPECT_EQ(roundToUnits(exact, floors + left, false), expected) << "trial " << trial;
  }
}

TEST(ExactRows, UnitsOnFloatsAreTakenWhereTheLargeOnesRoundedUp) {
  // Large entries 24 units past the float grid's 32 round up by 8 each; the small ones are
  // whole, so their floors leave nothing: the units taken come from the first small ones.
  std::vector<double> exact = {0x1p28 + 24, 0x1p28 + 24, 0x1p28 + 24};
  for (int k = 0; k < 100; ++k) exact.push_back(1000);
  int64_t whole = 0;
  for (double v : exact) whole += static_cast<int64_t>(v);
  const std::vector<int64_t> units = roundToUnits(exact, whole, true);
  EXPECT_EQ(total(units), whole);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(units[k], (int64_t{1} << 28) + 32);
  for (int k = 3; k < 27; ++k) EXPECT_EQ(units[k], 999) << k;
  for (int k = 27; k < 103; ++k) EXPECT_EQ(units[k], 1000) << k;
  // More units left than small entries: several each.
  const std::vector<int64_t> few =
      roundToUnits({0x1p28 + 24, 0x1p28 + 24, 1000, 1000}, (int64_t{1} << 29) + 2048, true);
  EXPECT_EQ(few,
            (std::vector<int64_t>{(int64_t{1} << 28) + 32, (int64_t{1} << 28) + 32, 992, 992}));
  // No small entry: the row keeps what the rounding left over, under 2^-24 of its sum.
  const std::vector<int64_t> large = roundToUnits({0x1p31 + 100, 0x1p31 - 100}, whole, true);
  EXPECT_EQ(large, (std::vector<int64_t>{int64_t{1} << 31, (int64_t{1} << 31) - 128}));
}

}  // namespace
}  // namespace radiosity::formfactor
