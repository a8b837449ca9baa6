#include "solve/discretisation_error.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/corner_radiosity.h"
#include "formfactor/emitter_set.h"
#include "measure/light_error.h"
#include "partition/owner_queries.h"
#include "solve/direct_light.h"
#include "solve/owned_patch_rays.h"
#include "solve/solve.h"
#include "trace/counter_rng.h"
#include "trace/parallel_for.h"
#include "trace/sample_warps.h"

namespace radiosity::solve {

namespace {

constexpr uint32_t kDiscretisationStream = 0xd15c;

// ρ_j times the gradient of H inside patch j, per channel: a hit at offset d from j's centroid
// scores slope·d. In double: B spans the scales of the stability checks (1e±30 scenes, extreme
// emission), and a float slope would overflow there.
struct ReflectedSlope {
  std::array<Vec3, 3> channel{};

  Rgb at(const Vec3& d) const {
    return {dot(channel[0], d), dot(channel[1], d), dot(channel[2], d)};
  }
};

// Patch j's point at barycentric (u, v) less its centroid.
Vec3 offsetFromCentroid(const Mesh& patches, int64_t j, double u, double v) {
  const Triangle& c = patches.triangles[j];
  const Vec3& v0 = patches.vertices[c[0]];
  return (u - 1.0 / 3) * (patches.vertices[c[1]] - v0) +
         (v - 1.0 / 3) * (patches.vertices[c[2]] - v0);
}

// The estimate's rays a rank keeps the hits of at a time (16 B each) before the ranks exchange
// those that landed on each other's patches.
constexpr int64_t kRaysPerExchange = int64_t{1} << 18;

// Where each row's estimated error comes from: the part of δH_i whose rays hit patch j, summed
// signed over those rays (a linear variation that the kernel does not weigh cancels), weighted
// as the error measure weighs row i's relative error, added up per patch j in fixed point.
class SourceAttribution {
 public:
  using Hits = std::vector<std::pair<int64_t, Rgb>>;

  /// `slope`: of this rank's rows.
  SourceAttribution(MPI_Comm comm, const Mesh& patches, partition::PatchRange owned,
                    const std::vector<Rgb>& irradiance, const std::vector<ReflectedSlope>& slope)
      : comm_(comm), owned_(owned), weight_(owned.size()), local_(patches.triangleCount(), 0) {
    std::vector<double> area(owned.size());
    std::vector<Rgb> reflectance(owned.size()), radiosity(owned.size());
    for (int64_t i = owned.begin; i < owned.end; ++i) {
      const int64_t r = i - owned.begin;
      area[r] = patches.area(i);
      reflectance[r] = patches.reflectance[i];
      for (int c = 0; c < 3; ++c)
        radiosity[r][c] = patches.emission[i][c] + reflectance[r][c] * irradiance[r][c];
    }
    const std::array<double, 3> mean = reflectingMean(comm, area, reflectance, radiosity);
    for (size_t r = 0; r < weight_.size(); ++r)
      for (int c = 0; c < 3; ++c)
        if (reflectance[r][c] > 0)
          weight_[r][c] = area[r] * reflectance[r][c] /
                          std::max(radiosity[r][c], kLightErrorFloorShare * mean[c]);
    // The largest deviation any hit can score, per channel, bounds every row's sum: the scale
    // keeps the grand total below 2^50, so the integer sums cannot overflow.
    Rgb largest{0, 0, 0};
    for (int64_t j = owned.begin; j < owned.end; ++j) {
      double reach = 0;
      for (auto [u, v] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}})
        reach = std::max(reach, length(offsetFromCentroid(patches, j, u, v)));
      for (int c = 0; c < 3; ++c)
        largest[c] = std::max(largest[c], length(slope[j - owned.begin].channel[c]) * reach);
    }
    MPI_Allreduce(MPI_IN_PLACE, largest.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
    double bound = 0;
    for (const Rgb& w : weight_)
      for (int c = 0; c < 3; ++c) bound += w[c] * largest[c];
    MPI_Allreduce(MPI_IN_PLACE, &bound, 1, MPI_DOUBLE, MPI_SUM, comm);
    scale_ = bound > 0 && std::isfinite(bound) ? 0x1p50 / bound : 0;
  }

  /// Row i's hits (patch, ρ_j times the deviation there) of its `rays` rays. Safe to call from
  /// several threads at once, for different rows.
  void addRow(int64_t i, Hits& hits, int64_t rays) {
    if (scale_ == 0) return;
    std::sort(hits.begin(), hits.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const Rgb& w = weight_[i - owned_.begin];
    for (size_t first = 0; first < hits.size();) {
      Rgb sum{0, 0, 0};
      size_t end = first;
      for (; end < hits.size() && hits[end].first == hits[first].first; ++end)
        for (int c = 0; c < 3; ++c) sum[c] += hits[end].second[c];
      double value = 0;
      for (int c = 0; c < 3; ++c) value += w[c] * std::abs(sum[c]);
      // (atomic: rows on other threads add to the same patches; integers, so in any order)
      std::atomic_ref<int64_t>(local_[hits[first].first])
          .fetch_add(std::llround(value / static_cast<double>(rays) * scale_),
                     std::memory_order_relaxed);
      first = end;
    }
  }

  /// Every patch's sum, on every rank. Collective.
  void finish(DiscretisationReport& report) {
    MPI_Allreduce(MPI_IN_PLACE, local_.data(), static_cast<int>(local_.size()), MPI_INT64_T,
                  MPI_SUM, comm_);
    report.sourceError = std::move(local_);
    report.sourceScale = scale_ > 0 ? scale_ : 1;
  }

 private:
  MPI_Comm comm_;
  partition::PatchRange owned_;
  std::vector<Rgb> weight_;
  std::vector<int64_t> local_;
  double scale_ = 0;
};

int64_t directSamples(int64_t raysPerPatch) { return std::max<int64_t>(16, raysPerPatch / 4); }

// ρ times the gradient of H inside this rank's rows, from its own rows' H and direct light and
// those of the patches around them, asked of their owners: no array of the whole scene's values
// (the slopes of other ranks' patches stay there too: the ray pass asks for the deviations).
std::vector<ReflectedSlope> reflectedSlopes(MPI_Comm comm, const DiscretisationInputs& in) {
  const Mesh& patches = in.patches;
  const partition::PatchRange owned = in.owned;
  const std::vector<Rgb>& irradiance = in.irradiance;
  std::vector<ReflectedSlope> mine(owned.size());
  {
    // H is continuous across a change of material, where B = E + ρH jumps: unlike the
    // renderer's B, H is reconstructed across materials and split at creases only. A
    // least-squares gradient, not the corners' averages: those flatten H towards every crease
    // and contact line, where the kernel is largest, and the estimate came out well short of
    // the measured error. The direct light from each patch's own samples (a shadow edge inside
    // it), the rest of H (smooth, indirect) from the neighbours' means.
    // Of each row's direct light, its mean and, where a shadow edge crosses it, its slope (not
    // every sample's statistics).
    DirectParts direct =
        directLight(in.tracer, patches, owned, in.seed, directSamples(in.raysPerPatch), in.threads);
    const auto& edgeSlope = direct.edgeSlope;
    const SurfaceIds surfaces = setApart(oneSurface(patches), in.hidden);
    const GradientFit fit(patches, surfaces, owned.begin, owned.end);
    // H and the direct light's means of the patches around the rank's rows, from their owners.
    std::vector<int64_t> around = fit.neighboursOutside(owned.begin, owned.end);
    struct Question {
      int64_t patch;
    };
    std::vector<Question> questions(around.size());
    for (size_t k = 0; k < around.size(); ++k) questions[k].patch = around[k];
    const std::vector<std::array<Rgb, 2>> answers = partition::askOwners<std::array<Rgb, 2>>(
        comm, partition::RankBlocks(comm, owned), questions, [&](const Question& q) {
          const auto r = static_cast<size_t>(q.patch - owned.begin);
          return std::array<Rgb, 2>{irradiance[r], direct.mean[r]};
        });
    questions = {};
    std::vector<Rgb> aroundH(around.size()), aroundDirect(around.size());
    for (size_t k = 0; k < around.size(); ++k)
      aroundH[k] = answers[k][0], aroundDirect[k] = answers[k][1];
    const PatchValues all(owned.begin, irradiance, around, std::move(aroundH));
    const PatchValues directMean(owned.begin, direct.mean, std::move(around),
                                 std::move(aroundDirect));
    trace::parallelFor(
        owned.size(), in.threads,
        [&](int64_t begin, int64_t end, int) {
          auto edge = std::lower_bound(edgeSlope.begin(), edgeSlope.end(), begin,
                                       [](const auto& e, int64_t r) { return e.first < r; });
          for (int64_t r = begin; r < end; ++r) {
            const int64_t t = owned.begin + r;
            std::array<Vec3, 3> g = fit(t, all);
            // Where a shadow edge crosses patch t, the direct part's slope is its own samples'
            // instead of the one fitted to the neighbours' direct means.
            if (edge != edgeSlope.end() && edge->first == r) {
              const std::array<Vec3, 3> smoothDirect = fit(t, directMean);
              for (int c = 0; c < 3; ++c) g[c] = g[c] + (edge->second[c] - smoothDirect[c]);
              ++edge;
            }
            for (int c = 0; c < 3; ++c) mine[r].channel[c] = patches.reflectance[t][c] * g[c];
          }
        },
        kRowsPerTracePiece);
  }
  return mine;
}

}  // namespace

namespace {

// The hits of a piece's rays, `raysPerPatch` a row: the patch each scores (-1: none) and where
// on it (barycentric u, v).
struct PieceHits {
  std::vector<int64_t> patch;
  std::vector<float> u, v;
};

// The deviations at the hits that landed on other ranks' patches, from those patches' owners, in
// the rays' order; row r's begin at firstAnswer[r].
struct OtherRanksDeviations {
  std::vector<Rgb> answers;
  std::vector<int64_t> firstAnswer;
};

// Those of a piece's `hits`. Collective.
template <class Deviation>
OtherRanksDeviations deviationsOnOtherRanks(MPI_Comm comm, const partition::RankBlocks& blocks,
                                            partition::PatchRange owned, const PieceHits& hits,
                                            int64_t raysPerPatch, const Deviation& deviation) {
  struct Question {
    int64_t patch;
    float u, v;
  };
  const auto rows = static_cast<int64_t>(hits.patch.size()) / raysPerPatch;
  std::vector<Question> questions;
  OtherRanksDeviations found;
  found.firstAnswer.assign(static_cast<size_t>(rows) + 1, 0);
  for (int64_t r = 0; r < rows; ++r) {
    for (int64_t k = r * raysPerPatch; k < (r + 1) * raysPerPatch; ++k)
      if (hits.patch[k] >= 0 && !owned.contains(hits.patch[k]))
        questions.push_back({hits.patch[k], hits.u[k], hits.v[k]});
    found.firstAnswer[r + 1] = static_cast<int64_t>(questions.size());
  }
  found.answers = partition::askOwners<Rgb>(
      comm, blocks, questions, [&](const Question& q) { return deviation(q.patch, q.u, q.v); });
  return found;
}

// The gathering rays of row i: `raysPerPatch` cosine-weighted from uniform points on the patch,
// keyed by seed, patch and ray (traceOwnedPatches' aim).
struct GatheringRays {
  uint64_t seed = 0;
  int64_t raysPerPatch = 0;

  void operator()(int64_t i, const trace::PatchFrame& frame, double offset,
                  trace::SceneTracer::RayBatch& rays, int) const {
    for (int64_t k = 0; k < raysPerPatch; ++k) {
      const auto u = trace::uniforms(seed, static_cast<uint64_t>(i), static_cast<uint32_t>(k),
                                     kDiscretisationStream);
      const Vec3 origin =
          trace::pointOnTriangle(frame.v0, frame.v1, frame.v2, u[0], u[1]) + offset * frame.normal;
      const Vec3 direction = frame.cosineDirection(u[2], u[3]);
      rays.set(k, origin, direction, std::numeric_limits<double>::infinity());
    }
  }
};

}  // namespace

int64_t discretisationRays(int64_t samplesPerPatch) {
  return std::clamp<int64_t>(samplesPerPatch / 4, 16, 256);
}

DiscretisationEstimate estimateDiscretisationError(
    MPI_Comm comm, const DiscretisationInputs& in,
    const std::function<void(int64_t rowsDone)>& rowsDone) {
  const double start = MPI_Wtime();
  releaseFreedHeap();  // (the solve's Krylov basis and the calibration's rays are done)
  const Mesh& patches = in.patches;
  const partition::PatchRange owned = in.owned;
  const int64_t raysPerPatch = in.raysPerPatch;
  const int threads = in.threads;
  const std::vector<ReflectedSlope> slope = reflectedSlopes(comm, in);
  // ρ_j (H_lin − H̄_lin) at barycentric (u, v) of patch j, one of this rank's.
  auto deviation = [&](int64_t j, double u, double v) {
    return slope[j - owned.begin].at(offsetFromCentroid(patches, j, u, v));
  };
  // (its scratch gone first)
  SourceAttribution sources(comm, patches, owned, in.irradiance, slope);
  DiscretisationEstimate estimate;
  std::vector<Rgb>& error = estimate.error;
  std::vector<Rgb>& variance = estimate.variance;
  error.assign(owned.size(), Rgb{0, 0, 0});
  variance.assign(owned.size(), Rgb{0, 0, 0});
  const partition::RankBlocks blocks(comm, owned);

  // The rows a piece at a time: its rays traced, their hits on other ranks' patches answered by
  // the owners, then every row scored in its rays' order (the same sums as one pass).
  const int64_t rowsPerPiece = std::max<int64_t>(kRaysPerExchange / raysPerPatch,
                                                 kRowsPerTracePiece * 4 * std::max(threads, 1));
  int64_t pieces = (owned.size() + rowsPerPiece - 1) / rowsPerPiece;
  MPI_Allreduce(MPI_IN_PLACE, &pieces, 1, MPI_INT64_T, MPI_MAX, comm);
  PieceHits hit;  // per ray of the piece: the patch it scores, or -1, and where
  std::vector<SourceAttribution::Hits> rowHits(static_cast<size_t>(std::max(threads, 1)));
  const GatheringRays aim{in.seed, raysPerPatch};
  if (rowsDone) rowsDone(0);
  for (int64_t piece = 0; piece < pieces; ++piece) {
    const partition::PatchRange rows{std::min(owned.end, owned.begin + piece * rowsPerPiece),
                                     std::min(owned.end, owned.begin + (piece + 1) * rowsPerPiece)};
    const auto rays = static_cast<size_t>(rows.size() * raysPerPatch);
    hit.patch.assign(rays, -1);
    hit.u.resize(rays);
    hit.v.resize(rays);
    auto keep = [&](int64_t i, const trace::PatchFrame&, const trace::SceneTracer::RayBatch&,
                    const trace::SceneTracer::HitBatch& hits, int) {
      const int64_t first = (i - rows.begin) * raysPerPatch;
      for (int64_t k = 0; k < raysPerPatch; ++k) {
        const int64_t j = hits.patch[k];
        if (j < 0 || j == i || !hits.front[k]) continue;
        hit.patch[first + k] = j, hit.u[first + k] = hits.u[k], hit.v[first + k] = hits.v[k];
      }
    };
    traceOwnedPatches(in.tracer, patches, rows, raysPerPatch, threads, aim, keep);

    const OtherRanksDeviations others =
        deviationsOnOtherRanks(comm, blocks, owned, hit, raysPerPatch, deviation);

    trace::parallelFor(
        rows.size(), threads,
        [&](int64_t begin, int64_t end, int slot) {
          SourceAttribution::Hits& row = rowHits[slot];
          for (int64_t r = begin; r < end; ++r) {
            const int64_t i = rows.begin + r;
            int64_t answered = others.firstAnswer[r];
            Rgb sum{0, 0, 0}, squares{0, 0, 0};
            row.clear();
            for (int64_t k = r * raysPerPatch; k < (r + 1) * raysPerPatch; ++k) {
              const int64_t j = hit.patch[k];
              if (j < 0) continue;
              const Rgb d =
                  owned.contains(j) ? deviation(j, hit.u[k], hit.v[k]) : others.answers[answered++];
              for (int c = 0; c < 3; ++c) sum[c] += d[c], squares[c] += d[c] * d[c];
              if (in.attributeSources) row.push_back({j, d});
            }
            if (in.attributeSources) sources.addRow(i, row, raysPerPatch);
            const double n = static_cast<double>(raysPerPatch);
            for (int c = 0; c < 3; ++c) {
              const double mean = sum[c] / n;
              error[i - owned.begin][c] = mean;
              variance[i - owned.begin][c] = std::max(0.0, squares[c] / n - mean * mean) / (n - 1);
            }
          }
        },
        kRowsPerTracePiece);
    if (rowsDone) rowsDone(rows.end - owned.begin);
  }
  if (in.attributeSources) sources.finish(estimate.report);
  const int64_t cast = owned.size() * (raysPerPatch + directSamples(raysPerPatch));
  MPI_Allreduce(&cast, &estimate.report.rays, 1, MPI_INT64_T, MPI_SUM, comm);
  estimate.report.seconds = MPI_Wtime() - start;
  return estimate;
}

}  // namespace radiosity::solve
