#include "run/rank_balance.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "trace/random_streams.h"

namespace radiosity::run {

namespace {

double clockSeconds(clockid_t clock) {
  timespec now{};
  clock_gettime(clock, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

uint64_t mix(uint64_t z) {  // SplitMix64's finaliser: a scrambled order of a rank's runs
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Expected distinct patches N samples of row i hit, from a pilot row: each column j seen with
// the share f of the samples stands for f·(1 − (1 − p)^N)/p, p ≈ cos_i cos_j A_j / (π r²) the
// chance that one sample finds j (Horvitz–Thompson); near patches count about once, far ones
// up to N times their share.
double expectedNonzeros(const Mesh& patches, int64_t i, const SampleTally& pilot, int64_t row,
                        int64_t samples) {
  const Vec3 ci = patches.centroid(i), ni = patches.normal(i);
  const double scale = 1.0 / (4294967296.0 * static_cast<double>(pilot.samples));
  double expected = 0;
  for (int64_t k = pilot.rowStart[row]; k < pilot.rowStart[row + 1]; ++k) {
    const int64_t j = pilot.column[k];
    const Vec3 d = patches.centroid(j) - ci, nj = patches.normal(j);
    const double r2 = dot(d, d);
    double p = 1;
    if (r2 > 0) {
      const double cosines = std::fabs(dot(ni, d) * dot(nj, d)) / r2;
      p = std::clamp(cosines * patches.area(j) / (M_PI * r2), 1e-12, 1.0);
    }
    const double reached = -std::expm1(static_cast<double>(samples) * std::log1p(-p));
    expected += static_cast<double>(pilot.sum[k]) * scale * (p < 1 ? reached / p : 1.0);
  }
  return expected;
}

}  // namespace

double threadCpuSeconds() { return clockSeconds(CLOCK_THREAD_CPUTIME_ID); }
double processCpuSeconds() { return clockSeconds(CLOCK_PROCESS_CPUTIME_ID); }

double CostModel::imbalance(const partition::Blocks& blocks) const {
  // Cost of the patches [0, x): whole runs, then part of the run holding x.
  std::vector<double> prefix(perPatch.size() + 1, 0.0);
  for (size_t s = 0; s < perPatch.size(); ++s)
    prefix[s + 1] = prefix[s] + perPatch[s] * static_cast<double>(runStart[s + 1] - runStart[s]);
  auto before = [&](int64_t x) {
    const auto s = static_cast<size_t>(std::upper_bound(runStart.begin(), runStart.end(), x) -
                                       runStart.begin()) -
                   1;
    if (s >= perPatch.size()) return prefix.back();
    return prefix[s] + perPatch[s] * static_cast<double>(x - runStart[s]);
  };
  double largest = 0;
  for (int r = 0; r < blocks.ranks(); ++r) {
    const partition::PatchRange block = blocks.of(r);
    largest = std::max(largest, before(block.end) - before(block.begin));
  }
  const double mean = prefix.back() / blocks.ranks();
  return mean > 0 ? largest / mean : 1.0;
}

CostModel measureCosts(MPI_Comm comm, const trace::SceneTracer& tracer, const Mesh& patches,
                       const formfactor::Options& options, double* pilotShare) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const int64_t count = patches.triangleCount();
  const auto runs = static_cast<size_t>(
      std::max<int64_t>(1, std::min<int64_t>(count, kStretchesPerRank * ranks)));
  CostModel model;
  model.runStart.resize(runs + 1);
  for (size_t s = 0; s <= runs; ++s)
    model.runStart[s] = static_cast<int64_t>(static_cast<double>(count) * s / runs);
  model.runStart[runs] = count;
  const int64_t samples = std::max<int64_t>(1, options.raysPerPatch);
  const auto stride = static_cast<int64_t>(
      std::max(1.0, std::ceil(kPilotSamples / (kPilotShare * static_cast<double>(samples)))));

  formfactor::Options pilot = options;
  pilot.raysPerPatch = kPilotSamples;
  pilot.seed = trace::pilotSeed(options.seed);  // pilot rows are not the run's rows
  pilot.firstSample = 0;
  pilot.threads = 1;  // timed by this thread's clock
  formfactor::RowSampling sampling(tracer, patches, pilot);
  formfactor::Statistics statistics;

  // Per run: CPU seconds of the extra samples, their number, pilot rows, expected nonzeros
  // summed over the rows, CPU seconds of the short rows.
  constexpr size_t kFigures = 5;
  std::vector<double> measured(kFigures * runs, 0.0);
  const int64_t few = kPilotSamples / 4, more = kPilotSamples - few;
  std::vector<size_t> mine;
  for (size_t s = static_cast<size_t>(rank); s < runs; s += static_cast<size_t>(ranks))
    mine.push_back(s);
  std::sort(mine.begin(), mine.end(), [](size_t a, size_t b) { return mix(a) < mix(b); });
  for (size_t s : mine) {
    const int64_t begin = model.runStart[s], end = model.runStart[s + 1];
    if (begin == end) continue;
    // The patches of the run whose id is a multiple of the stride (its first when none is).
    int64_t first = (begin + stride - 1) / stride * stride;
    if (first >= end) first = begin;
    // Each pilot row twice, with kPilotSamples/4 and 3·kPilotSamples/4 samples: the difference
    // is the cost of half the samples without what a row costs whatever its samples (setting
    // up, sorting), which in so short a row would outweigh the rays.
    double difference = 0, shortRows = 0, rows = 0, nonzeros = 0;
    for (int64_t i = first; i < end; i += stride) {
      // (MIS's light choice of the row's cluster first: its pilot is shared by 64 rows, and
      // timed inside the short row it would swamp the difference)
      sampling.chooseLights(i, i + 1);
      const double start = threadCpuSeconds();
      sampling.sample(i, i + 1, 0, few, statistics);
      const double middle = threadCpuSeconds();
      const SampleTally row = sampling.sample(i, i + 1, few, more, statistics);
      difference += (threadCpuSeconds() - middle) - (middle - start);
      shortRows += middle - start;
      nonzeros += expectedNonzeros(patches, i, row, 0, samples);
      ++rows;
    }
    double* figures = &measured[kFigures * s];
    figures[0] = std::max(0.0, difference);
    figures[1] = rows * static_cast<double>(more - few);
    figures[2] = rows;
    figures[3] = nonzeros;
    figures[4] = shortRows;
  }
  // Each run was measured by one rank and is 0 elsewhere: the sums are exact, the same on every
  // rank.
  MPI_Allreduce(MPI_IN_PLACE, measured.data(), static_cast<int>(measured.size()), MPI_DOUBLE,
                MPI_SUM, comm);
  // What a row costs whatever its samples: the short rows' time less their samples' share, over
  // the whole curve (one figure: per run it would be a difference of small noisy times).
  double seconds = 0, pilotSamples = 0, shortSeconds = 0, pilotRows = 0;
  for (size_t s = 0; s < runs; ++s) {
    const double* figures = &measured[kFigures * s];
    seconds += figures[0], pilotSamples += figures[1], pilotRows += figures[2];
    if (figures[1] > 0)
      shortSeconds += figures[4] - static_cast<double>(few) * figures[0] / figures[1];
  }
  const double perSample = pilotSamples > 0 ? seconds / pilotSamples : 0;
  const double perRow = pilotRows > 0 ? std::max(0.0, shortSeconds / pilotRows) : 0;
  model.perPatch.resize(runs);
  for (size_t s = 0; s < runs; ++s) {
    const double* figures = &measured[kFigures * s];
    if (figures[2] == 0) continue;  // an empty run
    model.perPatch[s] = perRow + static_cast<double>(samples) * figures[0] / figures[1] +
                        kNonzeroInSamples * perSample * figures[3] / figures[2];
  }
  if (pilotShare)  // every pilot row costs kPilotSamples samples
    *pilotShare =
        pilotRows * kPilotSamples / (static_cast<double>(count) * static_cast<double>(samples));
  return model;
}

Balance balanceRows(MPI_Comm comm, const trace::SceneTracer& tracer, const Mesh& patches,
                    const formfactor::Options& options, BalanceMode mode) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const int64_t count = patches.triangleCount();
  Balance balance;
  balance.blocks = partition::Blocks::byCount(count, ranks);
  if (mode == BalanceMode::kCount) {
    balance.why = "--balance count";
  } else if (ranks == 1) {
    balance.why = "one rank";
  } else if (mode == BalanceMode::kAuto && ranks < kCostBalancedRanks) {
    balance.why = std::to_string(ranks) + " ranks (--balance auto cuts by cost from " +
                  std::to_string(kCostBalancedRanks) + " ranks up)";
  } else if (static_cast<double>(count) * static_cast<double>(options.raysPerPatch) <
             kSmallestBalancedStage) {
    balance.why = "the form-factor stage is too short for a pilot";
  } else if (count < kStretchesPerRank * ranks) {
    balance.why = "fewer patches than the pilot's runs";
  }
  if (!balance.why.empty()) return balance;

  const double start = MPI_Wtime();
  const CostModel model = measureCosts(comm, tracer, patches, options, &balance.pilotShare);
  // Computed alike on every rank from the same sums; rank 0's boundaries are sent all the same,
  // so that no rounding difference could ever give two ranks the same row.
  std::vector<int64_t> bound =
      partition::Blocks::byCost(model.runStart, model.perPatch, ranks).boundaries();
  MPI_Bcast(bound.data(), ranks + 1, MPI_INT64_T, 0, comm);
  balance.blocks = partition::Blocks(std::move(bound));
  balance.byCost = true;
  balance.predicted = model.imbalance(balance.blocks);
  balance.predictedByCount = model.imbalance(partition::Blocks::byCount(count, ranks));
  double seconds = MPI_Wtime() - start;
  MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm);
  balance.pilotSeconds = seconds;
  return balance;
}

std::string describeBalance(const Balance& balance) {
  char text[240];
  if (!balance.byCost) {
    std::snprintf(text, sizeof text, "balance: blocks by count (%s)", balance.why.c_str());
  } else {
    std::snprintf(text, sizeof text,
                  "balance: blocks by measured cost; pilot %.2g s (%.2g %% of the stage's "
                  "samples); predicted max/mean %.3f (by count %.3f)",
                  balance.pilotSeconds, 100 * balance.pilotShare, balance.predicted,
                  balance.predictedByCount);
  }
  return text;
}

std::string describeOutcome(MPI_Comm comm, double cpuSeconds, int64_t nonzeros) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  double local[2] = {cpuSeconds, static_cast<double>(nonzeros)}, largest[2], total[2];
  MPI_Allreduce(local, largest, 2, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm);
  auto ratio = [&](int k) { return total[k] > 0 ? largest[k] * ranks / total[k] : 1.0; };
  char text[200];
  std::snprintf(text, sizeof text,
                "balance: per rank, form-factor CPU time max/mean %.3f (max %.3g s), nonzeros "
                "max/mean %.3f",
                ratio(0), largest[0], ratio(1));
  return text;
}

}  // namespace radiosity::run
