// parallelFor on oneTBB: a task arena bounds the threads, tbb::parallel_for splits the range
// into pieces of at most `most` indices (the simple partitioner: TBB's adaptive one hands out
// pieces of an eighth of the range, and a thread that loses its core while on one holds up the
// end) and passes exceptions back.
#include "trace/parallel_for.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace radiosity::trace {

void parallelFor(int64_t count, int threads, const LoopBody& body, int64_t most) {
  if (count <= 0) return;
  // No more threads than the process may run (the cores, or what Embree's device was given):
  // TBB would warn on stderr and run fewer anyway.
  const auto allowed =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  threads = static_cast<int>(std::min<size_t>(std::max(threads, 1), allowed));
  if (threads <= 1) return body(0, count, 0);
  // One slot reserved for the caller, which takes slot 0; TBB's workers take the others.
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int64_t>(0, count, std::max<int64_t>(most, 1)),
        [&](const tbb::blocked_range<int64_t>& piece) {
          body(piece.begin(), piece.end(), tbb::this_task_arena::current_thread_index());
        },
        tbb::simple_partitioner());
  });
}

}  // namespace radiosity::trace
