// Rows of F by Monte Carlo. Hemisphere sampling: the share of cosine-distributed rays from
// patch i whose first hit is the front of patch j estimates F_ij without bias (the cosines and
// 1/(π r²) of the kernel cancel against the sampling density), a row has at most N entries, and
// in a closed scene it sums to exactly 1. Emitter MIS adds, per sample, a point uniform on the
// emitters' total area with a shadow ray; with the balance heuristic each of the two samples
// contributes p_h / (p_h + p_e) to the patch it reaches (p_h, p_e: the two densities of that
// direction in solid angle), which is at most 1 and unbiased.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <thread>
#include <unordered_map>

#include "core/error.h"
#include "formfactor/emitter_set.h"
#include "formfactor/exact_rows.h"
#include "formfactor/formfactor.h"
#include "formfactor/hemisphere_rays.h"
#include "formfactor/light_choice.h"
#include "formfactor/sobol.h"
#include "trace/counter_rng.h"
#include "trace/sample_warps.h"

namespace radiosity::formfactor {

namespace {

constexpr double kFixedPointOne = 0x1p32;  // contributions are summed in units of 2^-32

constexpr int64_t kOne = int64_t{1} << 32;  // a whole sample's contribution

// Shadow rays stop this share of the distance short of the sampled point, so that they test
// what lies between; asking for a hit on the point's own patch instead loses the points that a
// grazing ray, in float, finds first on a neighbouring patch.
constexpr double kShadowGap = 1e-4;

/// What one thread needs to sample rows; its statistics are summed at the end. A row is
/// sampled in three passes over its samples: make the rays, trace them (the tight loop of
/// bare Embree), score the hits.
class RowSampler {
 public:
  RowSampler(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
             const Options& options, const EmitterSet& emitters, const ExactRows* exact)
      : tracer_(tracer),
        exact_(exact),
        patches_(patches),
        normals_(normals),
        options_(options),
        emitters_(emitters),
        mis_(options.estimator == Estimator::kEmitterMis && !emitters.empty()) {
    if (patches.hasLabels()) statistics_.backFaceHitsByLabel.assign(patches.labelNames.size(), 0);
    setSamples(options.firstSample, options.raysPerPatch);
  }

  /// Samples row i, its emitter samples aimed by `lights`, and appends it to (sorted columns,
  /// fixed-point sums).
  void sampleRow(int64_t i, const LightChoice& lights, std::vector<int64_t>& columns,
                 std::vector<int64_t>& sums) {
    if (exact_) {
      statistics_.pairFactors += exact_->appendRow(i, options_.raysPerPatch, columns, sums);
      return;
    }
    lights_ = &lights;
    const trace::PatchFrame frame(patches_, i);
    makeHemisphereRays(patches_, i, options_.firstSample, options_.raysPerPatch, options_.seed,
                       rayOffset(tracer_, i), rays_, scratch_);
    tracer_.intersect(rays_, hits_);
    scoreHemisphereRays(i, frame);
    if (mis_) {
      makeEmitterRays(i, frame);
      tracer_.intersect(rays_, hits_);
      scoreEmitterRays();
    }
    if (fewHits_) return appendPairs(columns, sums);
    // The columns this row touched, in order, with their sums; the accumulator is left zero.
    // In column order: a sort of the touched columns, or, when they are many, one pass over
    // the accumulator (cheaper than sorting a row that touches a good share of the patches).
    const auto n = static_cast<int64_t>(accumulator_.size());
    const auto touched = static_cast<int64_t>(touched_.size());
    if (touched * 16 >= n) {
      for (int64_t column = 0; column < n; ++column) {
        if (accumulator_[column] == 0) continue;
        columns.push_back(column);
        sums.push_back(accumulator_[column]);
        accumulator_[column] = 0;
      }
    } else {
      std::sort(touched_.begin(), touched_.end());
      for (int64_t column : touched_) {
        columns.push_back(column);
        sums.push_back(accumulator_[column]);
        accumulator_[column] = 0;
      }
    }
    touched_.clear();
  }

  bool castsTwoRaysPerSample() const { return mis_; }

  /// The light choice of the cluster of patches [first, end), from a pilot of kLightPilotSamples
  /// MIS samples (emitter samples uniform over the area) spread over its patches: each light
  /// weighted by Σ MIS weight × the mean emission of the patch reached, an estimate of how much
  /// light it sends the cluster. The pilot's own scrambles keep it apart from the rows' samples.
  LightChoice pilot(int64_t first, int64_t end) {
    const int64_t each = (kLightPilotSamples + (end - first) - 1) / (end - first);
    const auto n = static_cast<size_t>(each * (end - first));
    pilotRays_.resize(n);
    pilotPatch_.resize(n);
    pilotTarget_.resize(n);
    pilotWeight_.resize(n);
    for (int64_t p = first; p < end; ++p) {
      makeHemisphereRays(patches_, p, 0, each, options_.seed, rayOffset(tracer_, p), rays_,
                         scratch_, kPilotHemisphereScramble);
      const auto at = static_cast<size_t>((p - first) * each);
      for (size_t k = 0; k < static_cast<size_t>(each); ++k) {
        pilotRays_.set(at + k, rayOrigin(k), rayDirection(k), rays_.tFar[k]);
        pilotPatch_[at + k] = p;
      }
    }
    tracer_.intersect(pilotRays_, hits_);
    statistics_.raysCast += static_cast<int64_t>(n);
    std::vector<std::pair<int64_t, double>> seen;
    const LightChoice byArea(emitters_);
    for (size_t k = 0; k < n; ++k) {
      const int64_t j = hits_.patch[k];
      if (j < 0 || j == pilotPatch_[k] || !hits_.front[k] || !isEmitter(j)) continue;
      const Vec3 direction = batchDirection(pilotRays_, k);
      const double ph = hemisphereDensity(direction, normals_[pilotPatch_[k]]);
      const double pe = emitterDensity(byArea, direction, j, hits_.distance[k]);
      seen.emplace_back(emitters_.lightOf(j), ph / (ph + pe) * meanEmission(j));
    }
    for (size_t k = 0; k < n; ++k) {  // emitter samples, from the hemisphere samples' points
      const int64_t p = pilotPatch_[k];
      const auto seeds = scrambleSeeds(options_.seed, p, kPilotEmitterScramble);
      const auto u = scrambledSobol(owenScramble(static_cast<uint32_t>(k % each), seeds[3]), seeds);
      const EmitterSet::Sample light = emitters_.sample(patches_, u[0], u[1], u[2]);
      const Vec3 origin = batchOrigin(pilotRays_, k), toward = light.point - origin;
      const double distance = length(toward);
      const Vec3 direction = (1.0 / distance) * toward;
      const double ph = hemisphereDensity(direction, normals_[p]);
      const double pe =
          light.patch == p ? 0.0 : emitterDensity(byArea, direction, light.patch, distance);
      const bool cast = ph > 0 && pe > 0;
      pilotWeight_[k] = cast ? ph / (ph + pe) * meanEmission(light.patch) : 0.0;
      pilotTarget_[k] = cast ? light.patch : -1;
      pilotRays_.set(k, origin, direction, cast ? distance * (1 - kShadowGap) : -1.0);
    }
    tracer_.intersect(pilotRays_, hits_);
    for (size_t k = 0; k < n; ++k) {
      if (pilotTarget_[k] < 0) continue;
      ++statistics_.raysCast;
      if (hits_.patch[k] < 0)
        seen.emplace_back(emitters_.lightOf(pilotTarget_[k]), pilotWeight_[k]);
    }
    // Summed per light in a fixed order: the same choice whichever thread or rank makes it.
    std::stable_sort(seen.begin(), seen.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::pair<int64_t, double>> weights;
    int64_t seenOnce = 0;  // lights one pilot sample alone reached
    for (size_t k = 0; k < seen.size(); ++k) {
      const int64_t light = seen[k].first;
      if (weights.empty() || weights.back().first != light) weights.emplace_back(light, 0.0);
      weights.back().second += seen[k].second;
      const bool first = k == 0 || seen[k - 1].first != light;
      const bool last = k + 1 == seen.size() || seen[k + 1].first != light;
      if (first && last) ++seenOnce;
    }
    const double unseen = seen.empty() ? 1.0 : double(seenOnce) / double(seen.size());
    return LightChoice(emitters_, weights, unseen);
  }

  /// The statistics gathered since the last call, which starts them again.
  Statistics takeStatistics() {
    Statistics taken = statistics_;
    statistics_ = Statistics();
    if (patches_.hasLabels())
      statistics_.backFaceHitsByLabel.assign(taken.backFaceHitsByLabel.size(), 0);
    return taken;
  }

  /// Samples [firstSample, firstSample + count) of every row from now on.
  void setSamples(int64_t firstSample, int64_t count) {
    options_.firstSample = firstSample;
    options_.raysPerPatch = count;
    rays_.resize(count);
    fewHits_ = count <= kFewHits && patches_.triangleCount() >= kLargeScene;
    // The dense accumulator only where it is used: 8 bytes per patch and thread.
    if (!fewHits_ && accumulator_.empty()) accumulator_.assign(patches_.triangleCount(), 0);
  }

 private:
  bool isEmitter(int64_t j) const {
    const Rgb& e = patches_.emission[j];
    return e[0] > 0 || e[1] > 0 || e[2] > 0;
  }

  double meanEmission(int64_t j) const {
    const Rgb& e = patches_.emission[j];
    return (e[0] + e[1] + e[2]) / 3;
  }

  // The two densities of a direction in solid angle: cosine-weighted hemisphere about the
  // patch's normal, and the light choice's point on emitter j seen at distance r.
  static double hemisphereDensity(Vec3 direction, Vec3 normal) {
    return std::max(0.0, dot(direction, normal)) / std::numbers::pi;
  }
  double emitterDensity(const LightChoice& lights, Vec3 direction, int64_t j, double r) const {
    const double cosine = -dot(direction, normals_[j]);
    return cosine > 0 ? r * r * lights.densityPerArea(j) / cosine : 0.0;
  }

  void add(int64_t column, int64_t amount) {
    if (amount == 0) return;
    if (fewHits_) {
      pairs_.push_back({column, amount});
    } else {
      if (accumulator_[column] == 0) touched_.push_back(column);
      accumulator_[column] += amount;
    }
  }

  // A row of few samples: its hits sorted by column and summed, with no access to the dense
  // accumulator, whose one int64 per patch (8 MB at 10^6 patches, per thread) costs a cache miss
  // per hit once the scene is large. The sums are integers: the same in any order.
  void appendPairs(std::vector<int64_t>& columns, std::vector<int64_t>& sums) {
    std::sort(pairs_.begin(), pairs_.end(),
              [](const Hit& a, const Hit& b) { return a.column < b.column; });
    for (size_t k = 0; k < pairs_.size(); ++k) {
      if (k == 0 || pairs_[k].column != pairs_[k - 1].column) {
        columns.push_back(pairs_[k].column);
        sums.push_back(0);
      }
      sums.back() += pairs_[k].amount;
    }
    pairs_.clear();
  }
  void add(int64_t column, double amount) {
    add(column, static_cast<int64_t>(std::llround(amount * kFixedPointOne)));
  }

  // Whether every ray of the batch from patch i met a back (or i itself).
  bool seesOnlyBacks(int64_t i) const {
    for (size_t k = 0; k < rays_.size(); ++k)
      if (hits_.patch[k] < 0 || (hits_.patch[k] != i && hits_.front[k])) return false;
    return !rays_.tFar.empty();
  }

  static Vec3 batchOrigin(const SceneTracer::RayBatch& rays, size_t k) {
    return {rays.originX[k], rays.originY[k], rays.originZ[k]};
  }
  static Vec3 batchDirection(const SceneTracer::RayBatch& rays, size_t k) {
    return {rays.directionX[k], rays.directionY[k], rays.directionZ[k]};
  }
  Vec3 rayOrigin(size_t k) const { return batchOrigin(rays_, k); }
  Vec3 rayDirection(size_t k) const { return batchDirection(rays_, k); }

  void scoreHemisphereRays(int64_t i, const trace::PatchFrame& frame) {
    statistics_.raysCast += static_cast<int64_t>(rays_.size());
    if (seesOnlyBacks(i)) {  // a hidden patch's row, or one inside a model wound inside out
      statistics_.backFaceHits += static_cast<int64_t>(rays_.size());
      statistics_.blindBackFaceHits += static_cast<int64_t>(rays_.size());
      if (patches_.hasLabels())
        for (size_t k = 0; k < rays_.size(); ++k)
          ++statistics_.backFaceHitsByLabel[patches_.label[hits_.patch[k]]];
      return;
    }
    for (size_t k = 0; k < rays_.size(); ++k) {
      const int64_t j = hits_.patch[k];
      if (j < 0) {
        ++statistics_.escapedRays;
      } else if (j == i || !hits_.front[k]) {
        ++statistics_.backFaceHits;  // absorbed: the back of a one-sided patch
        if (patches_.hasLabels()) ++statistics_.backFaceHitsByLabel[patches_.label[j]];
      } else if (mis_ && isEmitter(j)) {
        const Vec3 direction = rayDirection(k);
        const double ph = hemisphereDensity(direction, frame.normal);
        add(j, ph / (ph + emitterDensity(*lights_, direction, j, hits_.distance[k])));
      } else {
        add(j, kOne);
      }
    }
  }

  // The emitter sample of sample k leaves from the same point as its hemisphere ray (still in
  // the batch) and draws the same dimensions at a shuffled index (Burley's padding): sharing
  // the index would tie the light point to the receiver point for good.
  void makeEmitterRays(int64_t i, const trace::PatchFrame& frame) {
    const auto seeds = scrambleSeeds(options_.seed, i, kEmitterScramble);
    emitterTarget_.assign(rays_.size(), -1);
    emitterWeight_.assign(rays_.size(), 0.0);
    for (size_t k = 0; k < rays_.size(); ++k) {
      const auto index = static_cast<uint32_t>(options_.firstSample + static_cast<int64_t>(k));
      const auto u = scrambledSobol(owenScramble(index, seeds[3]), seeds);
      const EmitterSet::Sample light = lights_->sample(patches_, u[0], u[1], u[2]);
      const Vec3 origin = rayOrigin(k), toward = light.point - origin;
      const double distance = length(toward);
      const Vec3 direction = (1.0 / distance) * toward;
      const double ph = hemisphereDensity(direction, frame.normal);
      const double pe =
          light.patch == i ? 0.0 : emitterDensity(*lights_, direction, light.patch, distance);
      if (ph > 0 && pe > 0) {  // else the emitter faces away or lies behind: no ray
        emitterTarget_[k] = light.patch;
        emitterWeight_[k] = ph / (ph + pe);
      }
      rays_.set(k, origin, direction, emitterTarget_[k] >= 0 ? distance * (1 - kShadowGap) : -1.0);
    }
  }

  void scoreEmitterRays() {
    for (size_t k = 0; k < rays_.size(); ++k) {
      if (emitterTarget_[k] < 0) continue;
      ++statistics_.raysCast;
      // Visible when nothing lies between the origin and the sampled point.
      if (hits_.patch[k] < 0) add(emitterTarget_[k], emitterWeight_[k]);
    }
  }

  const SceneTracer& tracer_;
  const ExactRows* exact_;  ///< rows without rays, or null
  const Mesh& patches_;
  const std::vector<Vec3>& normals_;  ///< of every patch, computed once
  Options options_;
  const EmitterSet& emitters_;
  const LightChoice* lights_ = nullptr;  ///< of the row being sampled
  const bool mis_;
  Statistics statistics_;
  SceneTracer::RayBatch rays_;
  SceneTracer::HitBatch hits_;
  std::vector<uint32_t> scratch_;
  std::vector<int64_t> emitterTarget_;  ///< per sample: the emitter patch aimed at, or -1
  std::vector<double> emitterWeight_;   ///< per sample: its MIS weight p_h / (p_h + p_e)
  // The pilot's rays, the patch each leaves from, and each emitter sample's target and weight.
  SceneTracer::RayBatch pilotRays_;
  std::vector<int64_t> pilotPatch_, pilotTarget_;
  std::vector<double> pilotWeight_;
  /// Sums per column of the row being sampled (zero elsewhere): a dense array of one int64 per
  /// patch per thread, cheaper than sorting every contribution.
  std::vector<int64_t> accumulator_;
  std::vector<int64_t> touched_;  ///< columns with a nonzero sum in the current row
  /// Rows of at most kFewHits samples (MIS: two rays each) in scenes of at least kLargeScene
  /// patches are summed from their hits sorted (measured with bench/formfactor_ratio.sh: 4 %
  /// faster at 10^6 patches and 16 rays; at 5,000 patches and 256 rays the accumulator, then in
  /// cache, was faster than the sort).
  static constexpr int64_t kFewHits = 256, kLargeScene = int64_t{1} << 17;
  bool fewHits_ = false;
  struct Hit {
    int64_t column, amount;
  };
  std::vector<Hit> pairs_;  ///< the current row's hits, when fewHits_
};

void addStatistics(Statistics& total, const Statistics& part) {
  total.raysCast += part.raysCast;
  total.backFaceHits += part.backFaceHits;
  total.escapedRays += part.escapedRays;
  total.blindBackFaceHits += part.blindBackFaceHits;
  total.pairFactors += part.pairFactors;
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
        exact(options.exactRows ? std::make_unique<ExactRows>(mesh) : nullptr) {
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
  /// What each thread works with: its sampler, and the rows it sampled in the current block
  /// (columns, sums), kept from block to block and call to call (fresh buffers would fault their
  /// pages in again every time). A cache line of its own: the threads write their buffers' ends
  /// and their counts per hit, and two threads writing one line slow each other down.
  struct alignas(64) Worker {
    Worker(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
           const Options& options, const EmitterSet& emitters, const ExactRows* exact)
        : sampler(tracer, patches, normals, options, emitters, exact) {}
    RowSampler sampler;
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
  std::atomic<size_t> next{0};
  auto work = [&](int t) {
    for (size_t k; (k = next.fetch_add(1)) < missing.size();) {
      const int64_t first = missing[k] * kClusterPatches;
      made[k] = workers[t].sampler.pilot(
          first, std::min(first + kClusterPatches, patches.triangleCount()));
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (std::thread& helper : helpers) helper.join();
  for (size_t k = 0; k < missing.size(); ++k) clusterLights.emplace(missing[k], std::move(made[k]));
}

// A call samples its rows in blocks of at most this many entries (rows times the bound of a
// row's entries), each in the tally before the next starts: enough rows that the threads meet
// rarely, few enough that their buffers, reserved for a whole block, stay small (16 MB a thread,
// of which the pages a thread writes are resident).
constexpr int64_t kBlockEntries = int64_t{1} << 20;

// Calls of fewer rays than this per thread use fewer threads (measured: at 10^4 patches, 16
// rays a patch, the stage's pieces of 50 rows took 0.2 ms on one thread and ~3.5 ms on two,
// the second thread waiting for a core another process held).
constexpr int64_t kRaysPerThread = int64_t{1} << 14;

void RowSampling::Impl::sampleBlock(SampleTally& tally, int64_t first, int64_t end, int threads,
                                    int64_t done, const ProgressCallback& progress) {
  const int64_t rows = end - first;
  if (threads == 1) {  // one thread takes the rows in order: straight into the tally
    for (int64_t r = 0; r < rows; ++r) {
      workers[0].sampler.sampleRow(first + r, lightsOf(first + r), tally.column, tally.sum);
      tally.rowStart.push_back(static_cast<int64_t>(tally.column.size()));
      if (progress && (r + 1) % 64 == 0) progress(done + r + 1);
    }
    return;
  }
  // Threads take rows a run at a time and append them to their own buffers; where each row went
  // is recorded, and the rows are copied into the tally in order, so the result does not depend
  // on which thread computed which row. The copy is made while the threads sample on: whichever
  // thread finishes a run and finds no other copying copies the rows ready so far, and the
  // tally's fresh pages are faulted in by all threads, not by one after the others stopped.
  placement.resize(rows);
  ready = std::make_unique<std::atomic<bool>[]>(static_cast<size_t>(rows));
  std::vector<const int64_t*> columnOf(threads), sumOf(threads);
  for (int t = 0; t < threads; ++t) {
    // Room for the whole block, so that the buffers never move while another thread copies
    // from them (a row has at most perRow entries).
    Worker& w = workers[t];
    w.column.clear();
    w.sum.clear();
    w.column.reserve(static_cast<size_t>(rows * perRow));
    w.sum.reserve(static_cast<size_t>(rows * perRow));
    columnOf[t] = w.column.data();
    sumOf[t] = w.sum.data();
  }
  std::mutex copying;
  int64_t copied = 0;  // rows of the block in the tally (under `copying`)
  auto copyReady = [&] {
    for (; copied < rows && ready[copied].load(std::memory_order_acquire); ++copied) {
      const Placement& p = placement[copied];
      const int64_t* column = columnOf[p.thread] + p.offset;
      const int64_t* sum = sumOf[p.thread] + p.offset;
      tally.column.insert(tally.column.end(), column, column + p.length);
      tally.sum.insert(tally.sum.end(), sum, sum + p.length);
      tally.rowStart.push_back(static_cast<int64_t>(tally.column.size()));
    }
  };
  std::atomic<int64_t> next{0}, finished{0};
  auto work = [&](int t) {
    Worker& mine = workers[t];
    for (;;) {
      // Runs shrink towards the end of the block (a quarter of a thread's share of what is
      // left), so that the threads finish together; two atomic counters shared by the threads,
      // touched per row, would cost as much as sampling a row of few rays.
      const int64_t left = rows - next.load(std::memory_order_relaxed);
      const int64_t run = std::clamp<int64_t>(left / (4 * threads), 1, 64);
      const int64_t from = next.fetch_add(run);
      if (from >= rows) break;
      const int64_t to = std::min(rows, from + run);
      for (int64_t r = from; r < to; ++r) {
        const auto before = static_cast<int64_t>(mine.column.size());
        mine.sampler.sampleRow(first + r, lightsOf(first + r), mine.column, mine.sum);
        placement[r] = {t, before, static_cast<int64_t>(mine.column.size()) - before};
        ready[r].store(true, std::memory_order_release);
      }
      if (copying.try_lock()) {
        copyReady();
        copying.unlock();
      }
      const int64_t count = finished.fetch_add(to - from) + to - from;
      if (t == 0 && progress) progress(done + count);  // the caller's thread reports
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (std::thread& helper : helpers) helper.join();
  copyReady();  // what was left when the last run finished
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
  // A thread for every kRaysPerThread rays at least: starting and joining a thread costs as
  // much as tracing a few hundred rays, and longer when the cores are busy with other work.
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
  for (Impl::Worker& w : impl.workers) addStatistics(statistics, w.sampler.takeStatistics());
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

void addRowSums(const SparseRows& rows, Statistics& statistics) {
  addRowSums(rowSums(rows), statistics);
}

void addRowSums(const std::vector<double>& rowSums, Statistics& statistics) {
  for (double sum : rowSums) {
    statistics.minRowSum = std::min(statistics.minRowSum, sum);
    statistics.maxRowSum = std::max(statistics.maxRowSum, sum);
    statistics.sumRowSums += sum;
  }
}

}  // namespace radiosity::formfactor
