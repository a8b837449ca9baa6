// Private to io/store: the check both collective writers (result, checkpoint) make before they
// create anything, that the ranks' blocks of rows tile all rows in rank order.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace radiosity {

/// How checkRankBlocksTile's messages name the blocks: "rank 2 <startsAt> from 10 but ..." and
/// "the ranks <hold> 9 <rows> of 10" ({"owns patches", "own", "patches"}).
struct BlockWords {
  const char* startsAt;
  const char* hold;
  const char* rows;
};

/// Throws std::invalid_argument unless rank r's block [first, first + count) starts where the
/// blocks of the ranks before it end and the blocks together hold `total` rows. `gathered` holds
/// every rank's `width` values in rank order (MPI_Allgather), its first and count first;
/// `checkRank(r, values)` checks rank r's values before its block is (what the ranks must agree
/// on, such as the total).
template <class CheckRank>
void checkRankBlocksTile(const std::vector<int64_t>& gathered, size_t width, int64_t total,
                         const BlockWords& words, CheckRank checkRank) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  int64_t expectedFirst = 0;
  for (size_t r = 0; r < gathered.size() / width; ++r) {
    const int64_t* values = &gathered[width * r];
    checkRank(static_cast<int>(r), values);
    if (values[0] != expectedFirst)
      fail("rank " + std::to_string(r) + " " + words.startsAt + " from " +
           std::to_string(values[0]) + " but the blocks of the ranks before it end at " +
           std::to_string(expectedFirst));
    expectedFirst += values[1];
  }
  if (expectedFirst != total)
    fail(std::string("the ranks ") + words.hold + " " + std::to_string(expectedFirst) + " " +
         words.rows + " of " + std::to_string(total));
}

}  // namespace radiosity
