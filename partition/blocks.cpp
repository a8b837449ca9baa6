#include "partition/partition.h"

namespace radiosity::partition {

PatchRange blockOf(int64_t count, int rank, int ranks) {
  int64_t base = count / ranks, extra = count % ranks;
  int64_t begin = rank * base + std::min<int64_t>(rank, extra);
  return {begin, begin + base + (rank < extra ? 1 : 0)};
}

int ownerOf(int64_t id, int64_t count, int ranks) {
  int64_t base = count / ranks, extra = count % ranks;
  int64_t bigBlocksEnd = extra * (base + 1);
  if (id < bigBlocksEnd) return static_cast<int>(id / (base + 1));
  return static_cast<int>(extra + (id - bigBlocksEnd) / base);
}

}  // namespace radiosity::partition
