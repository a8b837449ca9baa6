// The project's parallel loop (trace/parallel_for.h) and what runs on it: every index once, a
// slot per running thread, a worker's exception handed to the caller (no std::terminate), and
// the form-factor rows and verify's paths the same bits on one thread and on two.
#include "trace/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "verify/path_tracer.h"

namespace radiosity {
namespace {

TEST(ParallelFor, CoversEveryIndexOnceInShortPiecesAndSlotsBelowTheThreads) {
  for (int threads : {1, 2, 4}) {
    const int64_t count = 10007;
    std::vector<std::atomic<int>> seen(count);
    std::atomic<bool> slotsInRange{true}, callerInSlotZero{true}, piecesShort{true};
    const std::thread::id caller = std::this_thread::get_id();
    trace::parallelFor(
        count, threads,
        [&](int64_t begin, int64_t end, int slot) {
          if (slot < 0 || slot >= threads) slotsInRange = false;
          if (threads > 1 && end - begin > 16) piecesShort = false;
          if (std::this_thread::get_id() == caller && slot != 0) callerInSlotZero = false;
          for (int64_t k = begin; k < end; ++k) ++seen[k];
        },
        16);
    for (int64_t k = 0; k < count; ++k) ASSERT_EQ(seen[k], 1) << k << ", " << threads << " threads";
    EXPECT_TRUE(slotsInRange) << threads << " threads";
    EXPECT_TRUE(callerInSlotZero) << threads << " threads";
    EXPECT_TRUE(piecesShort) << threads << " threads";
  }
  bool called = false;
  trace::parallelFor(0, 2, [&](int64_t, int64_t, int) { called = true; });
  EXPECT_FALSE(called);
}

// No two pieces at once in one slot: state kept per slot needs no lock.
TEST(ParallelFor, ASlotRunsOnePieceAtATime) {
  const int threads = 2;
  std::vector<std::atomic<int>> running(threads);
  std::atomic<bool> overlap{false};
  trace::parallelFor(2000, threads, [&](int64_t begin, int64_t end, int slot) {
    if (running[slot].fetch_add(1) != 0) overlap = true;
    volatile double x = 0;
    for (int64_t k = begin; k < end; ++k) x = x + 1e-3 * static_cast<double>(k);
    running[slot].fetch_sub(1);
  });
  EXPECT_FALSE(overlap);
}

TEST(ParallelFor, AnExceptionOnTheCallingThreadReachesTheCaller) {
  EXPECT_THROW(trace::parallelFor(100, 2,
                                  [](int64_t begin, int64_t end, int) {
                                    if (begin <= 50 && 50 < end) throw std::runtime_error("fifty");
                                  }),
               std::runtime_error);
  EXPECT_THROW(
      trace::parallelFor(100, 1, [](int64_t, int64_t, int) { throw std::logic_error("one"); }),
      std::logic_error);
}

// The caller's pieces wait until another thread has taken one, and only that thread throws: the
// exception is a worker's, and it arrives here with its type and message.
TEST(ParallelFor, AWorkersExceptionReachesTheCaller) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> workerStarted{false};
  try {
    trace::parallelFor(64, 2, [&](int64_t, int64_t, int) {
      if (std::this_thread::get_id() != caller) {
        workerStarted = true;
        throw std::runtime_error("from a worker");
      }
      const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (!workerStarted && std::chrono::steady_clock::now() < giveUp)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    if (!workerStarted) GTEST_SKIP() << "no second thread took a piece (one core?)";
    FAIL() << "the worker's exception was lost";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "from a worker");
  }
}

bool sameTally(const formfactor::SampleTally& a, const formfactor::SampleTally& b) {
  return a.firstRow == b.firstRow && a.samples == b.samples && a.rowStart == b.rowStart &&
         a.column == b.column && a.sum == b.sum;
}

// Rows with emitter MIS and light choices (several rooms, several lights): the pilots and the
// rows on two threads give one thread's tally and counts bit for bit.
TEST(ParallelFor, FormFactorRowsAreTheSameOnOneAndTwoThreads) {
  const Mesh rooms = partition::orderAlongCurve(loadScene("builtin:rooms?patches=6000"));
  trace::SceneTracer tracer(rooms);
  const int64_t n = rooms.triangleCount();
  formfactor::Statistics one, two;
  const formfactor::SampleTally single = formfactor::sampleRows(
      tracer, rooms, 0, n, {24, 7, formfactor::Estimator::kEmitterMis, 0, 1}, one);
  // Enough rays a call that RowSampling uses both threads (2^14 rays a thread at least).
  ASSERT_GE(n * 48, 2 * (int64_t{1} << 14));
  const formfactor::SampleTally twice = formfactor::sampleRows(
      tracer, rooms, 0, n, {24, 7, formfactor::Estimator::kEmitterMis, 0, 2}, two);
  EXPECT_TRUE(sameTally(single, twice));
  EXPECT_EQ(one.raysCast, two.raysCast);
  EXPECT_EQ(one.backFaceHits, two.backFaceHits);
  EXPECT_EQ(one.escapedRays, two.escapedRays);
}

TEST(ParallelFor, VerifyPathsAreTheSameOnOneAndTwoThreads) {
  const Mesh cornell = partition::refineToCount(loadScene("builtin:cornell"), 500);
  const verify::PathTracer tracer(cornell);
  std::vector<int64_t> patches;
  for (int64_t p = 0; p < cornell.triangleCount(); p += 7) patches.push_back(p);
  const auto single = tracer.trace(patches, 16, 3, 1);
  const auto twice = tracer.trace(patches, 16, 3, 2);
  ASSERT_EQ(single.size(), twice.size());
  for (size_t k = 0; k < single.size(); ++k) {
    EXPECT_EQ(single[k].radiosity, twice[k].radiosity) << "patch " << patches[k];
    EXPECT_EQ(single[k].standardError, twice[k].standardError) << "patch " << patches[k];
    EXPECT_EQ(single[k].rays, twice[k].rays) << "patch " << patches[k];
  }
  // A patch that does not exist: trace() throws on whichever thread takes it.
  patches.push_back(cornell.triangleCount());
  EXPECT_THROW(tracer.trace(patches, 16, 3, 2), std::out_of_range);
}

}  // namespace
}  // namespace radiosity
