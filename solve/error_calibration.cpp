#include "solve/error_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "measure/light_error.h"
#include "trace/random_streams.h"

namespace radiosity::solve {

namespace {

constexpr int kReplicates = 4;
// Rows gathered again, in all: a sixteenth of the patches, within these bounds.
constexpr int64_t kFewestRows = 256, kMostRows = 2048;

bool reflects(const Rgb& rho) { return rho[0] > 0 || rho[1] > 0 || rho[2] > 0; }
bool emits(const Rgb& e) { return e[0] > 0 || e[1] > 0 || e[2] > 0; }

// Every rank's `local` one after the other, in rank order, on every rank.
template <typename T>
std::vector<T> gatherInRankOrder(MPI_Comm comm, const std::vector<T>& local, MPI_Datatype type) {
  int ranks;
  MPI_Comm_size(comm, &ranks);
  const int sent = static_cast<int>(local.size());
  std::vector<int> counts(ranks), offsets(ranks, 0);
  MPI_Allgather(&sent, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<T> all(offsets.back() + counts.back());
  MPI_Allgatherv(local.data(), sent, type, all.data(), counts.data(), offsets.data(), type, comm);
  return all;
}

// The `count` reflecting patches with the smallest hash of (seed, id), lit ones (B > 0 in
// `radiosity`, this rank's rows) first: a random subset that does not depend on the number of
// ranks, and that measures the error where there is light (a room on a ground of 10^6 m²: the
// room's rows, not the unlit ground's, whose zero variance would scale the estimate to nothing).
// Collective; every rank gets the same sorted ids.
std::vector<int64_t> choosePatches(MPI_Comm comm, const Mesh& patches, partition::PatchRange owned,
                                   const std::vector<Rgb>& radiosity, uint64_t seed,
                                   int64_t count) {
  trace::KeyedIds keyed;
  for (int64_t i = owned.begin; i < owned.end; ++i) {
    if (!reflects(patches.reflectance[i])) continue;
    const Rgb& b = radiosity[i - owned.begin];
    const uint64_t hash =
        trace::streamHash(seed, static_cast<uint64_t>(i), trace::kCalibrationSample);
    keyed.emplace_back(trace::sampleKey(hash, b[0] > 0 || b[1] > 0 || b[2] > 0), i);
  }
  // This rank's smallest, then the smallest of all ranks'.
  std::vector<int64_t> flat;
  for (const auto& [key, id] : trace::smallestKeys(std::move(keyed), count)) {
    flat.push_back(static_cast<int64_t>(key));
    flat.push_back(id);
  }
  const std::vector<int64_t> all = gatherInRankOrder(comm, flat, MPI_INT64_T);
  trace::KeyedIds candidates;
  for (size_t k = 0; k + 1 < all.size(); k += 2)
    candidates.emplace_back(static_cast<uint64_t>(all[k]), all[k + 1]);
  return trace::idsOf(trace::smallestKeys(std::move(candidates), count));
}

}  // namespace

std::vector<Rgb> fetchRows(MPI_Comm comm, int64_t patchCount, partition::PatchRange owned,
                           const std::vector<Rgb>& local, const std::vector<int64_t>& ids) {
  int ranks;
  MPI_Comm_size(comm, &ranks);
  // The ranks' blocks, however they were cut (by count or by cost): every rank's end.
  std::vector<int64_t> bound(ranks + 1, 0);
  MPI_Allgather(&owned.end, 1, MPI_INT64_T, bound.data() + 1, 1, MPI_INT64_T, comm);
  if (bound.back() != patchCount) throw std::logic_error("fetchRows: blocks do not cover patches");
  const partition::Blocks blocks(std::move(bound));
  // Ask each owner for its ids, in the order of `ids` grouped by owner.
  std::vector<std::vector<int64_t>> asked(ranks);
  for (int64_t id : ids) asked[blocks.owner(id)].push_back(id);
  std::vector<int> sendCounts(ranks), receiveCounts(ranks), sendOffsets(ranks, 0),
      receiveOffsets(ranks, 0);
  for (int r = 0; r < ranks; ++r) sendCounts[r] = static_cast<int>(asked[r].size());
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) {
    sendOffsets[r] = sendOffsets[r - 1] + sendCounts[r - 1];
    receiveOffsets[r] = receiveOffsets[r - 1] + receiveCounts[r - 1];
  }
  std::vector<int64_t> sendIds;
  for (const auto& a : asked) sendIds.insert(sendIds.end(), a.begin(), a.end());
  std::vector<int64_t> receivedIds(receiveOffsets.back() + receiveCounts.back());
  MPI_Alltoallv(sendIds.data(), sendCounts.data(), sendOffsets.data(), MPI_INT64_T,
                receivedIds.data(), receiveCounts.data(), receiveOffsets.data(), MPI_INT64_T, comm);
  // Answer with three doubles per id.
  std::vector<double> answers(3 * receivedIds.size());
  for (size_t k = 0; k < receivedIds.size(); ++k) {
    const Rgb& value = local[receivedIds[k] - owned.begin];
    std::copy(value.begin(), value.end(), answers.begin() + 3 * static_cast<int64_t>(k));
  }
  for (int r = 0; r < ranks; ++r) {
    sendCounts[r] *= 3, receiveCounts[r] *= 3, sendOffsets[r] *= 3, receiveOffsets[r] *= 3;
  }
  std::vector<double> values(3 * sendIds.size());
  MPI_Alltoallv(answers.data(), receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE,
                values.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, comm);
  // Back to the order of `ids`.
  std::vector<size_t> next(ranks, 0);
  std::vector<Rgb> result(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) {
    const int owner = blocks.owner(ids[k]);
    const size_t at = sendOffsets[owner] / 3 + next[owner]++;
    result[k] = {values[3 * at], values[3 * at + 1], values[3 * at + 2]};
  }
  return result;
}

namespace {

// One gathered patch of one channel: its measured variance, the model's two parts, the weight
// of its variance in the headline figure.
struct Observation {
  double measured, indirect, direct, weight;
};

// The scales (indirect, direct) of one channel. The mix t: indirect/Σ indirect and
// direct/Σ direct combined as u = t·a + (1 − t)·b, the t under which the measured variances,
// each s·u times a χ² with `dof` degrees of freedom over dof, are most likely (a grid over t,
// the best s in closed form); then s such that Σ weight·measured = Σ weight·model.
std::pair<double, double> fitScales(const std::vector<Observation>& data) {
  double totalIndirect = 0, totalDirect = 0;
  for (const Observation& o : data) totalIndirect += o.indirect, totalDirect += o.direct;
  if (!(totalIndirect > 0) && !(totalDirect > 0)) return {1.0, 1.0};
  double bestMix = totalIndirect > 0 ? 1.0 : 0.0;
  if (totalIndirect > 0 && totalDirect > 0) {
    double best = -std::numeric_limits<double>::infinity();
    for (int step = 0; step <= 100; ++step) {
      const double t = step / 100.0;
      double ratio = 0, logs = 0;
      int n = 0;
      for (const Observation& o : data) {
        const double u = t * o.indirect / totalIndirect + (1 - t) * o.direct / totalDirect;
        if (!(u > 0)) continue;
        ratio += o.measured / u, logs += std::log(u), ++n;
      }
      if (n == 0 || !(ratio > 0)) continue;
      const double s = ratio / n;                         // the likeliest scale for this mix
      const double likelihood = -n * std::log(s) - logs;  // up to terms free of (s, t)
      if (likelihood > best) best = likelihood, bestMix = t;
    }
  }
  const double a = totalIndirect > 0 ? bestMix / totalIndirect : 0.0;
  const double b = totalDirect > 0 ? (1 - bestMix) / totalDirect : 0.0;
  double measured = 0, modelled = 0;
  for (const Observation& o : data) {
    measured += o.weight * o.measured;
    modelled += o.weight * (a * o.indirect + b * o.direct);
  }
  if (!(modelled > 0) || !std::isfinite(measured / modelled)) return {1.0, 1.0};
  const double s = measured / modelled;
  return {s * a, s * b};
}

// The chosen rows this rank owns (`mine`), gathered again kReplicates times under independent
// scrambles: replicate r of mine[m] at r * mine.size() + m.
std::vector<formfactor::SampleTally> gatherReplicas(const trace::SceneTracer& tracer,
                                                    const Mesh& patches,
                                                    const formfactor::Options& sampling,
                                                    const std::vector<int64_t>& mine,
                                                    formfactor::Statistics& statistics) {
  std::vector<formfactor::SampleTally> replicas;
  for (int r = 0; r < kReplicates; ++r) {
    formfactor::Options options = sampling;
    options.seed =
        trace::streamHash(sampling.seed, static_cast<uint64_t>(r), trace::kCalibrationReplicaSeed);
    options.firstSample = 0;
    options.threads = 1;
    formfactor::RowSampling rows(tracer, patches, options);
    for (int64_t i : mine)
      replicas.push_back(rows.sample(i, i + 1, 0, sampling.raysPerPatch, statistics));
  }
  return replicas;
}

// B at every column the replicas reach, fetched from the ranks that own them.
class ColumnValues {
 public:
  ColumnValues(MPI_Comm comm, int64_t patchCount, partition::PatchRange owned,
               const std::vector<Rgb>& radiosity,
               const std::vector<formfactor::SampleTally>& replicas) {
    for (const auto& tally : replicas)
      columns_.insert(columns_.end(), tally.column.begin(), tally.column.end());
    std::sort(columns_.begin(), columns_.end());
    columns_.erase(std::unique(columns_.begin(), columns_.end()), columns_.end());
    values_ = fetchRows(comm, patchCount, owned, radiosity, columns_);
  }
  const Rgb& operator()(int64_t column) const {
    return values_[std::lower_bound(columns_.begin(), columns_.end(), column) - columns_.begin()];
  }

 private:
  std::vector<int64_t> columns_;
  std::vector<Rgb> values_;
};

// One gathered row's replicates: each one's estimate of H_i per channel, and the model of that
// estimate's variance evaluated on the replicate's own row (as the solve evaluates it on its
// rows), summed over the replicates in its two parts.
struct Replicates {
  std::array<std::array<double, kReplicates>, 3> h{};
  std::array<double, 3> indirectModel{}, directModel{};
};

// Adds one replicate's part (x = B on the patches that do not emit, part 0, or that do, part 1)
// to its estimate h[c][r] and to the model. Σ F x² − (Σ F x)² = Σ F (x − x̄)² + x̄² s (1 − s),
// s = Σ F, x̄ = Σ F x / s: summed that way, without the cancellation of the first form (2e-16 of
// B², which in a closed box of uniform B is all there is), 1 − s exact from the integer sums.
void addPart(const Mesh& patches, const formfactor::SampleTally& tally, int part, int r,
             const ColumnValues& valueOf, double samples, Replicates& out) {
  const double scale = 0x1p-32 / static_cast<double>(tally.samples);
  auto inPart = [&](int64_t j) { return emits(patches.emission[j]) == (part == 1); };
  int64_t hits = 0;
  std::array<double, 3> first{};
  for (size_t k = 0; k < tally.column.size(); ++k) {
    if (!inPart(tally.column[k])) continue;
    hits += tally.sum[k];
    const Rgb b = valueOf(tally.column[k]);
    for (int c = 0; c < 3; ++c) first[c] += tally.sum[k] * scale * b[c];
  }
  if (hits == 0) return;
  const double share = static_cast<double>(hits) * scale;
  const double rest = static_cast<double>(tally.samples * (int64_t{1} << 32) - hits) * scale;
  std::array<double, 3> mean{}, spread{};
  for (int c = 0; c < 3; ++c) mean[c] = first[c] / share, out.h[c][r] += first[c];
  for (size_t k = 0; k < tally.column.size(); ++k) {
    if (!inPart(tally.column[k])) continue;
    const Rgb b = valueOf(tally.column[k]);
    for (int c = 0; c < 3; ++c)
      spread[c] += tally.sum[k] * scale * (b[c] - mean[c]) * (b[c] - mean[c]);
  }
  for (int c = 0; c < 3; ++c) {
    const double model = std::max(0.0, spread[c] + mean[c] * mean[c] * share * rest) / samples;
    (part == 0 ? out.indirectModel : out.directModel)[c] += model;
  }
}

// Every rank's observations (4 numbers per patch and channel, in patch order), fitted per
// channel: the same on any number of ranks.
VarianceScale fitAllChannels(MPI_Comm comm, const std::vector<double>& local) {
  const std::vector<double> all = gatherInRankOrder(comm, local, MPI_DOUBLE);
  VarianceScale scale;
  for (int c = 0; c < 3; ++c) {
    std::vector<Observation> data;
    for (size_t k = 4 * c; k + 3 < all.size(); k += 12) {
      if (std::isnan(all[k])) continue;
      data.push_back({all[k], all[k + 1], all[k + 2], all[k + 3]});
    }
    const auto [indirectScale, directScale] = fitScales(data);
    scale.indirect[c] = indirectScale;
    scale.direct[c] = directScale;
  }
  return scale;
}

}  // namespace

CalibrationReport calibrateSamplingError(MPI_Comm comm, const trace::SceneTracer& tracer,
                                         const Mesh& patches, partition::PatchRange owned,
                                         const formfactor::Options& sampling,
                                         const std::vector<Rgb>& radiosity) {
  const double start = MPI_Wtime();
  CalibrationReport report;
  const int64_t patchCount = patches.triangleCount();
  const int64_t rowsInAll = std::clamp<int64_t>(patchCount / 16, kFewestRows, kMostRows);
  const std::vector<int64_t> chosen = choosePatches(comm, patches, owned, radiosity, sampling.seed,
                                                    std::max<int64_t>(1, rowsInAll / kReplicates));
  report.patches = static_cast<int64_t>(chosen.size());
  report.replicates = kReplicates;

  // Each rank gathers its own chosen rows again.
  std::vector<int64_t> mine;
  for (int64_t i : chosen)
    if (owned.contains(i)) mine.push_back(i);
  formfactor::Statistics statistics;
  const std::vector<formfactor::SampleTally> replicas =
      gatherReplicas(tracer, patches, sampling, mine, statistics);
  const ColumnValues valueOf(comm, patchCount, owned, radiosity, replicas);

  // Per gathered patch and channel: the measured variance, the model's parts, and the weight
  // of its variance in the headline figure, w = A ρ² / max(B, floor)² (measure/light_error.h).
  std::vector<double> area(owned.size());
  for (int64_t r = 0; r < owned.size(); ++r) area[r] = patches.area(owned.begin + r);
  const std::vector<Rgb> ownedReflectance(patches.reflectance.begin() + owned.begin,
                                          patches.reflectance.begin() + owned.end);
  const std::array<double, 3> mean = reflectingMean(comm, area, ownedReflectance, radiosity);
  // The model's divisor, as the solve's (solve/sampling_error.h): the samples per row.
  const double samples = static_cast<double>(sampling.raysPerPatch);
  std::vector<double> local;  // 4 numbers per patch and channel, NaN where ρ_c = 0
  for (size_t m = 0; m < mine.size(); ++m) {
    const int64_t i = mine[m], row = i - owned.begin;
    // The mean of the replicates' models is what their spread is compared with (see the
    // header).
    Replicates replicates;
    for (int r = 0; r < kReplicates; ++r) {
      for (int part = 0; part < 2; ++part)
        addPart(patches, replicas[r * mine.size() + m], part, r, valueOf, samples, replicates);
    }
    for (int c = 0; c < 3; ++c) {
      const double rho = patches.reflectance[i][c];
      const double floor = std::max(radiosity[row][c], kLightErrorFloorShare * mean[c]);
      const auto& h = replicates.h[c];
      // (in two passes: the one-pass form's cancellation, 2e-16 of H², is no variance)
      const double average = std::accumulate(h.begin(), h.end(), 0.0) / kReplicates;
      double measured = 0;
      for (double value : h) measured += (value - average) * (value - average);
      measured /= kReplicates - 1;
      const bool counts = rho > 0 && floor > 0;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      local.push_back(counts ? measured : nan);
      local.push_back(replicates.indirectModel[c] / kReplicates);
      local.push_back(replicates.directModel[c] / kReplicates);
      local.push_back(counts ? area[row] * rho * rho / (floor * floor) : 0.0);
    }
  }
  report.scale = fitAllChannels(comm, local);
  MPI_Allreduce(&statistics.raysCast, &report.rays, 1, MPI_INT64_T, MPI_SUM, comm);
  report.seconds = MPI_Wtime() - start;
  return report;
}

}  // namespace radiosity::solve
