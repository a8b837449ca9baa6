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
#include <numbers>
#include <thread>

#include "formfactor/counter_rng.h"
#include "formfactor/emitter_set.h"
#include "formfactor/formfactor.h"
#include "formfactor/sample_warps.h"
#include "formfactor/sobol.h"

namespace radiosity::formfactor {

namespace {

// Scramble seeds of one (seed, patch): one set for the hemisphere sample (point, direction),
// one for the emitter sample (which emitter, point on it).
constexpr uint32_t kHemisphereScramble = 0;
constexpr uint32_t kEmitterScramble = 1;
constexpr double kFixedPointOne = 0x1p32;  // contributions are summed in units of 2^-32

std::array<uint32_t, 4> scrambleSeeds(uint64_t seed, int64_t patch, uint32_t stream) {
  auto bits = philox4x32({0, stream, static_cast<uint32_t>(patch),
                          static_cast<uint32_t>(static_cast<uint64_t>(patch) >> 32)},
                         {static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32)});
  return {bits[0], bits[1], bits[2], bits[3]};
}

struct Contribution {
  int64_t column;
  int64_t amount;  ///< units of 2^-32
  bool operator<(const Contribution& other) const { return column < other.column; }
};

/// What one thread needs to sample rows; its statistics are summed at the end.
class RowSampler {
 public:
  RowSampler(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
             const Options& options, const EmitterSet& emitters)
      : tracer_(tracer),
        patches_(patches),
        normals_(normals),
        options_(options),
        emitters_(emitters),
        mis_(options.estimator == Estimator::kEmitterMis && !emitters.empty()),
        offset_(rayOffset(tracer)) {
    if (patches.hasLabels()) statistics_.backFaceHitsByLabel.assign(patches.labelNames.size(), 0);
  }

  /// Samples row i into (sorted columns, fixed-point sums).
  void sampleRow(int64_t i, std::vector<int64_t>& columns, std::vector<int64_t>& sums) {
    const PatchFrame frame(patches_, i);
    const auto hemisphereSeeds = scrambleSeeds(options_.seed, i, kHemisphereScramble);
    const auto emitterSeeds = scrambleSeeds(options_.seed, i, kEmitterScramble);
    contributions_.clear();
    for (int64_t k = 0; k < options_.raysPerPatch; ++k) {
      const auto index = static_cast<uint32_t>(options_.firstSample + k);
      const auto u = scrambledSobol(index, hemisphereSeeds);
      const Vec3 point = pointOnTriangle(frame.v0, frame.v1, frame.v2, u[0], u[1]);
      const Vec3 origin = point + offset_ * frame.normal;
      castHemisphereRay(i, frame, origin, frame.cosineDirection(u[2], u[3]));
      // The emitter sample draws the same dimensions at a shuffled index (Burley's padding):
      // sharing the index would tie the light point to the receiver point for good.
      if (mis_) {
        castEmitterRay(i, frame, origin,
                       scrambledSobol(owenScramble(index, emitterSeeds[3]), emitterSeeds));
      }
    }
    std::sort(contributions_.begin(), contributions_.end());
    columns.clear();
    sums.clear();
    for (const Contribution& c : contributions_) {
      if (c.amount == 0) continue;
      if (!columns.empty() && columns.back() == c.column) {
        sums.back() += c.amount;
      } else {
        columns.push_back(c.column);
        sums.push_back(c.amount);
      }
    }
  }

  const Statistics& statistics() const { return statistics_; }

 private:
  bool isEmitter(int64_t j) const {
    const Rgb& e = patches_.emission[j];
    return e[0] > 0 || e[1] > 0 || e[2] > 0;
  }

  // The two densities of a direction in solid angle: cosine-weighted hemisphere, and a point
  // uniform on the emitters' area seen at distance r on emitter j.
  static double hemisphereDensity(Vec3 direction, const PatchFrame& frame) {
    return std::max(0.0, dot(direction, frame.normal)) / std::numbers::pi;
  }
  double emitterDensity(Vec3 direction, int64_t j, double r) const {
    const double cosine = -dot(direction, normals_[j]);
    return cosine > 0 ? r * r / (emitters_.totalArea() * cosine) : 0.0;
  }

  void add(int64_t column, double amount) {
    contributions_.push_back({column, std::llround(amount * kFixedPointOne)});
  }

  void castHemisphereRay(int64_t i, const PatchFrame& frame, Vec3 origin, Vec3 direction) {
    ++statistics_.raysCast;
    auto hit = tracer_.intersect(origin, direction, 0.0);
    if (!hit) {
      ++statistics_.escapedRays;
    } else if (hit->patch == i || dot(direction, normals_[hit->patch]) >= 0) {
      ++statistics_.backFaceHits;  // absorbed: the back of a one-sided patch
      if (patches_.hasLabels()) ++statistics_.backFaceHitsByLabel[patches_.label[hit->patch]];
    } else if (mis_ && isEmitter(hit->patch)) {
      const double ph = hemisphereDensity(direction, frame);
      add(hit->patch, ph / (ph + emitterDensity(direction, hit->patch, hit->distance)));
    } else {
      add(hit->patch, 1.0);
    }
  }

  void castEmitterRay(int64_t i, const PatchFrame& frame, Vec3 origin,
                      const std::array<double, 4>& u) {
    const EmitterSet::Sample light = emitters_.sample(patches_, u[0], u[1], u[2]);
    if (light.patch == i) return;
    const Vec3 toward = light.point - origin;
    const double distance = length(toward);
    const Vec3 direction = (1.0 / distance) * toward;
    const double ph = hemisphereDensity(direction, frame);
    const double pe = emitterDensity(direction, light.patch, distance);
    if (ph <= 0 || pe <= 0) return;  // the emitter faces away, or lies behind the receiver
    ++statistics_.raysCast;
    // Visible when the first thing along the shadow ray is the sampled emitter patch.
    auto hit = tracer_.intersect(origin, direction, 0.0, distance * (1 + 1e-6));
    if (hit && hit->patch == light.patch) add(light.patch, ph / (ph + pe));
  }

  const SceneTracer& tracer_;
  const Mesh& patches_;
  const std::vector<Vec3>& normals_;  ///< of every patch, computed once
  const Options& options_;
  const EmitterSet& emitters_;
  const bool mis_;
  const double offset_;
  Statistics statistics_;
  std::vector<Contribution> contributions_;
};

void addStatistics(Statistics& total, const Statistics& part) {
  total.raysCast += part.raysCast;
  total.backFaceHits += part.backFaceHits;
  total.escapedRays += part.escapedRays;
  if (total.backFaceHitsByLabel.size() < part.backFaceHitsByLabel.size()) {
    total.backFaceHitsByLabel.resize(part.backFaceHitsByLabel.size(), 0);
  }
  for (size_t k = 0; k < part.backFaceHitsByLabel.size(); ++k) {
    total.backFaceHitsByLabel[k] += part.backFaceHitsByLabel[k];
  }
}

}  // namespace

double rayOffset(const SceneTracer& tracer) {
  // Relative to the scene, not an absolute epsilon: Embree works in float, whose rounding
  // grows with the coordinates, and the same scene at any scale must give the same rows.
  return 1e-5 * tracer.sceneSize();
}

SampledRay hemisphereRay(const Mesh& patches, int64_t patch, int64_t sample, uint64_t seed,
                         double offset) {
  const PatchFrame frame(patches, patch);
  const auto u = scrambledSobol(static_cast<uint32_t>(sample),
                                scrambleSeeds(seed, patch, kHemisphereScramble));
  const Vec3 point = pointOnTriangle(frame.v0, frame.v1, frame.v2, u[0], u[1]);
  return {point + offset * frame.normal, frame.cosineDirection(u[2], u[3])};
}

SampleTally sampleRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress) {
  if (options.raysPerPatch < 1 || options.firstSample < 0 ||
      options.firstSample + options.raysPerPatch > (int64_t{1} << 32)) {
    throw Error(exit_code::kUsage, "samples per patch must lie in [1, 2^32)");
  }
  const EmitterSet emitters(patches);
  std::vector<Vec3> normals(patches.triangleCount());
  for (int64_t t = 0; t < patches.triangleCount(); ++t) normals[t] = patches.normal(t);
  const int64_t rows = endPatch - firstPatch;
  const int threads =
      static_cast<int>(std::clamp<int64_t>(options.threads, 1, std::max<int64_t>(rows, 1)));

  // Threads take rows one at a time; each row lands in its own slot, so the result does not
  // depend on which thread computed it.
  std::vector<std::vector<int64_t>> columns(rows), sums(rows);
  std::atomic<int64_t> next{0}, done{0};
  std::vector<RowSampler> samplers;
  samplers.reserve(threads);
  for (int t = 0; t < threads; ++t)
    samplers.emplace_back(tracer, patches, normals, options, emitters);
  auto work = [&](int t) {
    for (int64_t r; (r = next.fetch_add(1)) < rows;) {
      samplers[t].sampleRow(firstPatch + r, columns[r], sums[r]);
      const int64_t finished = done.fetch_add(1) + 1;
      if (t == 0 && progress) progress(finished);  // the caller's thread reports
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (std::thread& helper : helpers) helper.join();
  if (progress) progress(rows);

  SampleTally tally;
  tally.firstRow = firstPatch;
  tally.samples = options.raysPerPatch;
  for (int64_t r = 0; r < rows; ++r) {
    tally.column.insert(tally.column.end(), columns[r].begin(), columns[r].end());
    tally.sum.insert(tally.sum.end(), sums[r].begin(), sums[r].end());
    tally.rowStart.push_back(static_cast<int64_t>(tally.column.size()));
    std::vector<int64_t>().swap(columns[r]);
    std::vector<int64_t>().swap(sums[r]);
  }
  for (const RowSampler& sampler : samplers) addStatistics(statistics, sampler.statistics());
  return tally;
}

SparseRows computeRows(const SceneTracer& tracer, const Mesh& patches, int64_t firstPatch,
                       int64_t endPatch, const Options& options, Statistics& statistics,
                       const ProgressCallback& progress) {
  SparseRows rows = toFormFactors(
      sampleRows(tracer, patches, firstPatch, endPatch, options, statistics, progress));
  statistics.minRowSum = rows.rowCount() > 0 ? 2.0 : 0.0;
  statistics.maxRowSum = 0.0;
  statistics.sumRowSums = 0.0;
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    double sum = 0;
    for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) sum += rows.value[k];
    statistics.minRowSum = std::min(statistics.minRowSum, sum);
    statistics.maxRowSum = std::max(statistics.maxRowSum, sum);
    statistics.sumRowSums += sum;
  }
  return rows;
}

}  // namespace radiosity::formfactor
