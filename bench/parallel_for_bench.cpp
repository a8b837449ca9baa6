// The project's parallel loop (trace/parallel_for.h, oneTBB) against the hand-rolled fork-join it
// replaced (std::thread per call, rows taken in shrinking runs from an atomic counter), on the
// form-factor stage's own work: each patch's hemisphere rays made and traced, a ray batch per
// thread. Calls of a whole scene, and calls of 2^15 rays (the least on which the stage runs two
// threads: formfactor/row_sampling.cpp, kRaysPerThread) or 2^17, show the work split and the
// cost of a call.
//
// The scene, its size and the rays per patch come from the environment (bench/bench_scene.h).
// Sample runs:
//   build/bench/parallel_for_bench --benchmark_repetitions=9
//       --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "bench/bench_scene.h"
#include "trace/parallel_for.h"

namespace radiosity {
namespace {

using bench::benchPatches;
using bench::benchTracer;
using bench::kRaysPerPatch;

/// What a thread keeps from row to row: its ray batch, hits and a checksum of the hits.
struct alignas(64) ThreadState {
  trace::SceneTracer::RayBatch rays;
  trace::SceneTracer::HitBatch hits;
  uint64_t checksum = 0;
};

void traceRow(ThreadState& state, int64_t patch) {
  const trace::SceneTracer& tracer = benchTracer();
  formfactor::hemisphereRays(benchPatches(), patch, 0, kRaysPerPatch, 1,
                             formfactor::rayOffset(tracer, patch), state.rays);
  tracer.intersect(state.rays, state.hits);
  for (int64_t j : state.hits.patch) state.checksum += j < 0 ? 1u : static_cast<uint64_t>(j);
}

/// Rows [first, end) on `threads` threads as formfactor/thread_sampler.cpp did before
/// trace::parallelFor: a std::thread per helper per call, runs of rows from an atomic counter.
void handRolled(std::vector<ThreadState>& states, int64_t first, int64_t end, int threads) {
  const int64_t rows = end - first;
  std::atomic<int64_t> next{0};
  auto work = [&](int t) {
    for (;;) {
      const int64_t left = rows - next.load(std::memory_order_relaxed);
      const int64_t run = std::clamp<int64_t>(left / (4 * threads), 1, 64);
      const int64_t from = next.fetch_add(run);
      if (from >= rows) break;
      for (int64_t r = from; r < std::min(rows, from + run); ++r) traceRow(states[t], first + r);
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (std::thread& helper : helpers) helper.join();
}

/// The same on trace::parallelFor, in pieces as formfactor/row_sampling.cpp cuts them.
void onParallelFor(std::vector<ThreadState>& states, int64_t first, int64_t end, int threads) {
  const int64_t most = std::clamp<int64_t>((end - first) / (4 * threads), 1, 64);
  trace::parallelFor(
      end - first, threads,
      [&](int64_t begin, int64_t stop, int slot) {
        for (int64_t r = begin; r < stop; ++r) traceRow(states[slot], first + r);
      },
      most);
}

// Arguments: threads, rays a call (0: the whole scene in one call).
template <auto kLoop>
void BM_Rows(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int64_t n = benchPatches().triangleCount();
  const int64_t pieces =
      state.range(1) > 0 ? std::clamp(n * kRaysPerPatch / state.range(1), int64_t{1}, n) : 1;
  benchTracer();
  std::vector<ThreadState> states(threads);
  int64_t rays = 0;
  for (auto _ : state) {
    for (int64_t p = 0; p < pieces; ++p)
      kLoop(states, n * p / pieces, n * (p + 1) / pieces, threads);
    rays += n * kRaysPerPatch;
  }
  for (const ThreadState& s : states) benchmark::DoNotOptimize(s.checksum);
  state.counters["rays/s"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

// The same calls for both: threads, rays a call. Wall-clock time: with two threads the CPU time
// of the main thread alone would say nothing.
void calls(benchmark::internal::Benchmark* b) {
  b->Args({2, 0})->Args({2, 1 << 15})->Args({2, 1 << 17});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
BENCHMARK(BM_Rows<handRolled>)->Name("BM_HandRolled")->Apply(calls);
BENCHMARK(BM_Rows<onParallelFor>)->Name("BM_ParallelFor")->Apply(calls);

}  // namespace
}  // namespace radiosity

BENCHMARK_MAIN();
