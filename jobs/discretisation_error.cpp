#include "jobs/discretisation_error.h"

#include <algorithm>
#include <limits>

#include "formfactor/counter_rng.h"
#include "formfactor/sample_warps.h"
#include "io/core/corner_radiosity.h"

namespace radiosity::jobs {

namespace {

constexpr uint32_t kDiscretisationStream = 0xd15c;

// Every patch's B on every rank (rank blocks are in id order, cut by count or by cost). Counted
// in whole patches (three doubles each), so that MPI's int counts reach 2^31 patches, not 2^31/3.
std::vector<Rgb> gatherAll(MPI_Comm comm, const std::vector<Rgb>& local, int64_t count) {
  int ranks;
  MPI_Comm_size(comm, &ranks);
  MPI_Datatype rgb;
  MPI_Type_contiguous(3, MPI_DOUBLE, &rgb);
  MPI_Type_commit(&rgb);
  std::vector<int> counts(ranks), offsets(ranks, 0);
  const int mine = static_cast<int>(local.size());
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<Rgb> all(count);
  MPI_Allgatherv(local.data(), mine, rgb, all.data(), counts.data(), offsets.data(), rgb, comm);
  MPI_Type_free(&rgb);
  return all;
}

}  // namespace

int64_t discretisationRays(int64_t samplesPerPatch) {
  return std::clamp<int64_t>(samplesPerPatch / 4, 16, 256);
}

void estimateDiscretisationError(MPI_Comm comm, const formfactor::SceneTracer& tracer,
                                 const Mesh& patches, partition::PatchRange owned, uint64_t seed,
                                 int64_t raysPerPatch, const std::vector<Rgb>& irradiance,
                                 const std::vector<uint8_t>& hidden, std::vector<Rgb>& error,
                                 std::vector<Rgb>& variance, DiscretisationReport& report) {
  const double start = MPI_Wtime();
  const int64_t count = patches.triangleCount();
  const std::vector<Rgb> all = gatherAll(comm, irradiance, count);
  std::vector<Vec3> normal(count);
  std::vector<double> area(count);
  for (int64_t t = 0; t < count; ++t) normal[t] = patches.normal(t), area[t] = patches.area(t);
  // H is continuous across a change of material, where B = E + ρH jumps: unlike the renderer's
  // B, H is averaged across materials and split at creases only.
  const CornerRadiosity corners =
      cornerRadiosity(patches, normal, area, all, setApart(oneSurface(patches), hidden));
  // B(y) = E_j + ρ_j H(y) on patch j: the reconstruction's deviation from its own patch mean
  // at barycentric (u, v), times ρ_j.
  auto deviation = [&](int64_t j, double u, double v) {
    const auto& c = corners[j];
    const Rgb at = interpolate(c, u, v);
    Rgb d;
    for (int k = 0; k < 3; ++k)
      d[k] = patches.reflectance[j][k] * (at[k] - (c[0][k] + c[1][k] + c[2][k]) / 3);
    return d;
  };

  const double offset = formfactor::rayOffset(tracer);
  formfactor::SceneTracer::RayBatch rays;
  formfactor::SceneTracer::HitBatch hits;
  rays.resize(raysPerPatch);
  error.assign(owned.size(), Rgb{0, 0, 0});
  variance.assign(owned.size(), Rgb{0, 0, 0});
  for (int64_t i = owned.begin; i < owned.end; ++i) {
    const formfactor::PatchFrame frame(patches, i);
    for (int64_t k = 0; k < raysPerPatch; ++k) {
      const auto u = formfactor::uniforms(seed, static_cast<uint64_t>(i), static_cast<uint32_t>(k),
                                          kDiscretisationStream);
      const Vec3 origin = formfactor::pointOnTriangle(frame.v0, frame.v1, frame.v2, u[0], u[1]) +
                          offset * frame.normal;
      const Vec3 direction = frame.cosineDirection(u[2], u[3]);
      rays.set(k, origin, direction, std::numeric_limits<double>::infinity());
    }
    tracer.intersect(rays, hits);
    Rgb sum{0, 0, 0}, squares{0, 0, 0};
    for (int64_t k = 0; k < raysPerPatch; ++k) {
      const int64_t j = hits.patch[k];
      if (j < 0 || j == i || !hits.front[k]) continue;
      const Rgb d = deviation(j, hits.u[k], hits.v[k]);
      for (int c = 0; c < 3; ++c) sum[c] += d[c], squares[c] += d[c] * d[c];
    }
    const double n = static_cast<double>(raysPerPatch);
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / n;
      error[i - owned.begin][c] = mean;
      variance[i - owned.begin][c] = std::max(0.0, squares[c] / n - mean * mean) / (n - 1);
    }
  }
  const int64_t cast = owned.size() * raysPerPatch;
  MPI_Allreduce(&cast, &report.rays, 1, MPI_INT64_T, MPI_SUM, comm);
  report.seconds = MPI_Wtime() - start;
}

}  // namespace radiosity::jobs
