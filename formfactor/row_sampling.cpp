// RowSampling and sampleRows: rows of F sampled on the threads of a rank, a ThreadSampler and a
// LightPilot per thread, the rows written to the tally in order whichever thread sampled them.
#include <algorithm>
#include <atomic>
#include <mutex>
#include <unordered_map>

#include "core/error.h"
#include "formfactor/formfactor.h"
#include "formfactor/light_pilot.h"
#include "formfactor/thread_sampler.h"
#include "trace/parallel_for.h"

namespace radiosity::formfactor {

namespace {

// A call samples its rows in blocks of at most this many entries (rows times the bound of a
// row's entries), each in the tally before the next starts: enough rows that the threads meet
// rarely, few enough that their buffers, reserved for a whole block, stay small (16 MB a thread,
// of which the pages a thread writes are resident).
constexpr int64_t kBlockEntries = int64_t{1} << 20;

// Calls of fewer rays than this per thread use fewer threads: handing rows to another thread
// costs more than sampling a few short rows, and far more when that thread waits for a core
// another process holds.
constexpr int64_t kRaysPerThread = int64_t{1} << 14;

// A thread takes a block's rows a piece at a time: at most this many rows, and at most a quarter
// of a thread's share of the block. Long enough that handing out a piece (shared counters the
// threads touch) costs little beside sampling it, even for rows of few rays; short enough that
// the threads finish together.
constexpr int64_t kMostRowsAPiece = 64;

void addStatistics(Statistics& total, const Statistics& part) {
  total.raysCast += part.raysCast;
  total.backFaceHits += part.backFaceHits;
  total.escapedRays += part.escapedRays;
  total.blindBackFaceHits += part.blindBackFaceHits;
  total.pairFactors += part.pairFactors;
  total.rowsOffTheirSum += part.rowsOffTheirSum;
  if (total.backFaceHitsByLabel.size() < part.backFaceHitsByLabel.size()) {
    total.backFaceHitsByLabel.resize(part.backFaceHitsByLabel.size(), 0);
  }
  for (size_t k = 0; k < part.backFaceHitsByLabel.size(); ++k) {
    total.backFaceHitsByLabel[k] += part.backFaceHitsByLabel[k];
  }
}

// Room in `tally` for the rest of a call's rows at the entries per row of the call so far
// (+25 %), once it has sampled `done` of its `rows`, starting at entry `start`: one call for many
// rows then writes them once, where a vector that doubles as it grows would copy them.
void reserveRest(SampleTally& tally, int64_t start, int64_t done, int64_t rows) {
  const auto size = static_cast<int64_t>(tally.column.size());
  const double perRow = static_cast<double>(size - start) / static_cast<double>(done);
  const auto estimate = static_cast<size_t>(size + perRow * static_cast<double>(rows - done));
  if (tally.column.capacity() >= estimate) return;
  // At least doubled: calls of a few blocks each, one after the other, then grow the tally as
  // a vector does, not by a copy per call.
  const size_t entries = std::max(static_cast<size_t>(1.25 * static_cast<double>(estimate)),
                                  2 * tally.column.capacity());
  tally.column.reserve(entries);
  tally.sum.reserve(entries);
  tally.rowStart.reserve(tally.rowStart.size() + static_cast<size_t>(rows - done));
}

}  // namespace

struct RowSampling::Impl {
  Impl(const SceneTracer& tracer, const Mesh& mesh, const Options& opts)
      : patches(mesh),
        options(opts),
        emitters(mesh),
        byArea(emitters),
        choosesLights(!options.exactRows && options.estimator == Estimator::kEmitterMis &&
                      emitters.lightCount() > 1),
        normals(mesh.triangleCount()),
        exact(options.exactRows
                  ? std::make_unique<ExactRows>(mesh, options.singlePrecision, options.pairsOnce)
                  : nullptr) {
    for (int64_t t = 0; t < mesh.triangleCount(); ++t) normals[t] = mesh.normal(t);
    const int threads = std::max(1, options.threads);
    workers.reserve(threads);
    for (int t = 0; t < threads; ++t)
      workers.emplace_back(tracer, mesh, normals, options, emitters, exact.get());
  }
  /// The light choice of the cluster of patch i (made by lightChoicesFor).
  const LightChoice& lightsOf(int64_t i) const {
    return choosesLights ? clusterLights.at(i / kClusterPatches) : byArea;
  }
  void lightChoicesFor(int64_t firstPatch, int64_t endPatch, int threads);

  /// Rows [first, end) appended to `tally` in order, on `threads` threads; `done`: the rows of
  /// this call sampled before them, for the progress reports.
  void sampleBlock(SampleTally& tally, int64_t first, int64_t end, int threads, int64_t done,
                   const ProgressCallback& progress);
  /// The same on one thread: straight into the tally.
  void sampleBlockInOrder(SampleTally& tally, int64_t first, int64_t end, int64_t done,
                          const ProgressCallback& progress);
  /// Each of the first `threads` workers' buffers emptied, with room for `rows` rows.
  void clearBuffers(int threads, int64_t rows);
  /// The rows of the block from `copied` on that are sampled, in order, appended to `tally`.
  void copyReadyRows(SampleTally& tally, int64_t rows, int64_t& copied) const;

  const Mesh& patches;
  Options options;
  EmitterSet emitters;
  LightChoice byArea;
  /// One light uniform by area serves every patch; pilots only when there is a choice.
  const bool choosesLights;
  /// Per cluster (patch id / kClusterPatches) sampled so far: its light choice, kept for later
  /// pieces of rows and of samples (tens of bytes a cluster).
  std::unordered_map<int64_t, LightChoice> clusterLights;
  std::vector<Vec3> normals;
  std::unique_ptr<ExactRows> exact;  ///< with Options::exactRows
  /// What each thread (parallelFor's slot) works with: its sampler and pilot, and the rows it
  /// sampled in the current block (columns, sums), kept from block to block and call to call
  /// (fresh buffers would fault their pages in again every time). A cache line of its own: the
  /// threads write their buffers' ends and their counts per hit, and two threads writing one
  /// line slow each other down.
  struct alignas(64) Worker {
    Worker(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
           const Options& options, const EmitterSet& emitters, const ExactRows* exact)
        : sampler(tracer, patches, normals, options, emitters, exact),
          pilot(tracer, patches, normals, emitters) {}
    ThreadSampler sampler;
    LightPilot pilot;
    std::vector<int64_t> column, sum;
  };
  std::vector<Worker> workers;
  /// Per row of the current block: the thread that sampled it and where its entries went.
  struct Placement {
    int thread;
    int64_t offset, length;
  };
  std::vector<Placement> placement;
  std::unique_ptr<std::atomic<bool>[]> ready;  ///< per row of the block: sampled, placed
  int64_t perRow = 0;  ///< bound on a row's entries: samples per row, times two for MIS
};

// The clusters of [firstPatch, endPatch) without a light choice get one, the threads taking
// clusters one at a time; each is the same whichever thread makes it.
void RowSampling::Impl::lightChoicesFor(int64_t firstPatch, int64_t endPatch, int threads) {
  if (!choosesLights || endPatch <= firstPatch) return;
  std::vector<int64_t> missing;
  for (int64_t c = firstPatch / kClusterPatches; c <= (endPatch - 1) / kClusterPatches; ++c) {
    if (clusterLights.count(c) == 0) missing.push_back(c);
  }
  std::vector<LightChoice> made(missing.size(), byArea);
  const auto count = static_cast<int64_t>(missing.size());
  trace::parallelFor(count, threads, [&](int64_t begin, int64_t end, int slot) {
    for (int64_t k = begin; k < end; ++k) {
      const int64_t first = missing[k] * kClusterPatches;
      made[k] = workers[slot].pilot.choose(
          first, std::min(first + kClusterPatches, patches.triangleCount()), options.seed);
    }
  });
  for (size_t k = 0; k < missing.size(); ++k) clusterLights.emplace(missing[k], std::move(made[k]));
}

void RowSampling::Impl::sampleBlockInOrder(SampleTally& tally, int64_t first, int64_t end,
                                           int64_t done, const ProgressCallback& progress) {
  for (int64_t r = 0; r < end - first; ++r) {
    workers[0].sampler.sampleRow(first + r, lightsOf(first + r), tally.column, tally.sum);
    tally.rowStart.push_back(static_cast<int64_t>(tally.column.size()));
    if (progress && (r + 1) % 64 == 0) progress(done + r + 1);
  }
}

void RowSampling::Impl::clearBuffers(int threads, int64_t rows) {
  for (int t = 0; t < threads; ++t) {
    // Room for the whole block, so that the buffers never move while another thread copies
    // from them (a row has at most perRow entries).
    Worker& w = workers[t];
    w.column.clear();
    w.sum.clear();
    w.column.reserve(static_cast<size_t>(rows * perRow));
    w.sum.reserve(static_cast<size_t>(rows * perRow));
  }
}

void RowSampling::Impl::copyReadyRows(SampleTally& tally, int64_t rows, int64_t& copied) const {
  for (; copied < rows && ready[copied].load(std::memory_order_acquire); ++copied) {
    const Placement& p = placement[copied];
    const int64_t* column = workers[p.thread].column.data() + p.offset;
    const int64_t* sum = workers[p.thread].sum.data() + p.offset;
    tally.column.insert(tally.column.end(), column, column + p.length);
    tally.sum.insert(tally.sum.end(), sum, sum + p.length);
    tally.rowStart.push_back(static_cast<int64_t>(tally.column.size()));
  }
}

// Threads take rows a piece at a time and append them to their own buffers; where each row went
// is recorded, and the rows are copied into the tally in order, so the result does not depend
// on which thread computed which row. The copy is made while the threads sample on: whichever
// thread finishes a piece and finds no other copying copies the rows ready so far, and the
// tally's fresh pages are faulted in by all threads, not by one after the others stopped.
void RowSampling::Impl::sampleBlock(SampleTally& tally, int64_t first, int64_t end, int threads,
                                    int64_t done, const ProgressCallback& progress) {
  if (threads == 1) return sampleBlockInOrder(tally, first, end, done, progress);
  const int64_t rows = end - first;
  placement.resize(rows);
  ready = std::make_unique<std::atomic<bool>[]>(static_cast<size_t>(rows));
  clearBuffers(threads, rows);
  std::mutex copying;
  int64_t copied = 0;  // rows of the block in the tally (under `copying`)
  std::atomic<int64_t> finished{0};
  const int64_t most = std::clamp<int64_t>(rows / (4 * threads), 1, kMostRowsAPiece);
  trace::parallelFor(
      rows, threads,
      [&](int64_t from, int64_t to, int slot) {
        Worker& mine = workers[slot];
        for (int64_t r = from; r < to; ++r) {
          const auto before = static_cast<int64_t>(mine.column.size());
          mine.sampler.sampleRow(first + r, lightsOf(first + r), mine.column, mine.sum);
          placement[r] = {slot, before, static_cast<int64_t>(mine.column.size()) - before};
          ready[r].store(true, std::memory_order_release);
        }
        if (std::unique_lock lock(copying, std::try_to_lock); lock) {
          copyReadyRows(tally, rows, copied);
        }
        const int64_t count = finished.fetch_add(to - from) + to - from;
        if (slot == 0 && progress) progress(done + count);  // the caller's thread reports
      },
      most);
  copyReadyRows(tally, rows, copied);  // what was left when the last piece finished
}

RowSampling::RowSampling(const SceneTracer& tracer, const Mesh& patches, const Options& options)
    : impl_(std::make_unique<Impl>(tracer, patches, options)) {}

RowSampling::~RowSampling() = default;

void RowSampling::chooseLights(int64_t firstPatch, int64_t endPatch) {
  impl_->lightChoicesFor(firstPatch, endPatch, 1);
}

SampleTally RowSampling::sample(int64_t firstPatch, int64_t endPatch, int64_t firstSample,
                                int64_t count, Statistics& statistics,
                                const ProgressCallback& progress) {
  SampleTally tally;
  sampleInto(tally, firstPatch, endPatch, firstSample, count, statistics, progress);
  return tally;
}

void RowSampling::sampleInto(SampleTally& tally, int64_t firstPatch, int64_t endPatch,
                             int64_t firstSample, int64_t count, Statistics& statistics,
                             const ProgressCallback& progress) {
  if (count < 1 || firstSample < 0 || firstSample + count > (int64_t{1} << 32)) {
    throw Error(exit_code::kUsage, "samples per patch must lie in [1, 2^32)");
  }
  if (tally.rowCount() == 0) {
    tally.firstRow = firstPatch;
    tally.samples = count;
  } else if (firstPatch != tally.firstRow + tally.rowCount() || count != tally.samples) {
    throw Error(exit_code::kFailure, "sampleInto: the rows do not follow on from the tally's");
  }
  Impl& impl = *impl_;
  const int64_t rows = endPatch - firstPatch;
  // A sample's rays, one or two, hit one patch each, and an exact row has an entry per patch at
  // most: a row has at most perRow entries.
  impl.perRow = impl.exact ? std::max<int64_t>(impl.patches.triangleCount(), 1)
                           : count * (impl.workers.front().sampler.castsTwoRaysPerSample() ? 2 : 1);
  // A thread for every kRaysPerThread rays at least.
  const int threads = static_cast<int>(
      std::clamp<int64_t>(static_cast<int64_t>(impl.workers.size()), 1,
                          std::max<int64_t>(rows * impl.perRow / kRaysPerThread, 1)));
  for (Impl::Worker& w : impl.workers) w.sampler.setSamples(firstSample, count);
  impl.lightChoicesFor(firstPatch, endPatch, threads);

  const int64_t block = std::max<int64_t>(16 * threads, kBlockEntries / impl.perRow);
  const auto start = static_cast<int64_t>(tally.column.size());
  for (int64_t done = 0; done < rows;) {
    const int64_t end = std::min(rows, done + block);
    impl.sampleBlock(tally, firstPatch + done, firstPatch + end, threads, done, progress);
    done = end;
    if (done < rows) reserveRest(tally, start, done, rows);
  }
  if (progress) progress(rows);
  for (Impl::Worker& w : impl.workers) {
    addStatistics(statistics, w.sampler.takeStatistics());
    statistics.raysCast += w.pilot.takeRaysCast();
  }
}

SampleTally sampleRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress) {
  Options perRow = options;
  perRow.threads = static_cast<int>(
      std::clamp<int64_t>(options.threads, 1, std::max<int64_t>(endPatch - firstPatch, 1)));
  return RowSampling(tracer, patches, perRow)
      .sample(firstPatch, endPatch, options.firstSample, options.raysPerPatch, statistics,
              progress);
}

}  // namespace radiosity::formfactor
