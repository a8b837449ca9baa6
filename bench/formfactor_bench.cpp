// How close the form-factor stage comes to bare Embree: the same rays (same scene, seed and
// samples per patch) cast once through formfactor::RowSampling, piece by piece as the stage
// calls it, and once as a plain rtcIntersect1 loop over pre-generated rays. The stage's extra
// work is sampling (Sobol', warps), the tally and the sort of each row; the ratio of the two
// times says what it costs.
//
// The scene, its size and the rays per patch come from the environment (defaults: the Cornell box
// at 5000 patches, 256 rays), so that the ratio can be measured as scenes outgrow the caches:
//   RADIOSITY_BENCH_SCENE=builtin:rooms RADIOSITY_BENCH_PATCHES=1000000 RADIOSITY_BENCH_RAYS=8
// Sample runs:
//   build/bench/formfactor_bench
//   bash bench/formfactor_ratio.sh          (medians of 9 repetitions and their ratio)
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_scene.h"

namespace radiosity {
namespace {

constexpr uint64_t kSeed = 1;

using bench::benchPatches;
using bench::benchTracer;
using bench::fromEnvironment;
using bench::kRaysPerPatch;

/// The hemisphere rays sampleRows() casts, as float arrays (origin and direction, xyz each).
struct RayBatch {
  std::vector<float> origin, direction;
  int64_t size() const { return static_cast<int64_t>(origin.size() / 3); }
};

const RayBatch& benchRays() {
  static const RayBatch rays = [] {
    const Mesh& patches = benchPatches();
    RayBatch batch;
    batch.origin.reserve(3 * patches.triangleCount() * kRaysPerPatch);
    batch.direction.reserve(3 * patches.triangleCount() * kRaysPerPatch);
    trace::SceneTracer::RayBatch row;
    for (int64_t i = 0; i < patches.triangleCount(); ++i) {
      formfactor::hemisphereRays(patches, i, 0, kRaysPerPatch, kSeed,
                                 formfactor::rayOffset(benchTracer(), i), row);
      for (int64_t k = 0; k < kRaysPerPatch; ++k) {
        batch.origin.insert(batch.origin.end(), {row.originX[k], row.originY[k], row.originZ[k]});
        batch.direction.insert(batch.direction.end(),
                               {row.directionX[k], row.directionY[k], row.directionZ[k]});
      }
    }
    return batch;
  }();
  return rays;
}

/// An Embree scene of the patches built as trace/scene_tracer.cpp builds it (robust, high
/// quality BVH over float vertices). Owns its device and scene.
class BareScene {
 public:
  explicit BareScene(const Mesh& mesh) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw std::runtime_error("cannot create an Embree device");
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int k = 0; k < 3; ++k) vertices[3 * v + k] = static_cast<float>(mesh.vertices[v][k]);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
    rtcCommitGeometry(geometry);
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
      throw std::runtime_error("cannot build the Embree scene");
  }
  ~BareScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  BareScene(const BareScene&) = delete;
  BareScene& operator=(const BareScene&) = delete;

  /// Casts rays [begin, end) of `rays` (tnear 0, tfar ∞, as sampleRows() does); returns the sum
  /// of the patch ids hit plus one per miss, so that nothing can be optimised away.
  uint64_t trace(const RayBatch& rays, int64_t begin, int64_t end) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    uint64_t checksum = 0;
    for (int64_t r = begin; r < end; ++r) {
      RTCRayHit rayHit{};
      rayHit.ray.org_x = rays.origin[3 * r];
      rayHit.ray.org_y = rays.origin[3 * r + 1];
      rayHit.ray.org_z = rays.origin[3 * r + 2];
      rayHit.ray.dir_x = rays.direction[3 * r];
      rayHit.ray.dir_y = rays.direction[3 * r + 1];
      rayHit.ray.dir_z = rays.direction[3 * r + 2];
      rayHit.ray.tnear = 0.0f;
      rayHit.ray.tfar = std::numeric_limits<float>::infinity();
      rayHit.ray.mask = 0xFFFFFFFFu;
      rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &context, &rayHit);
      checksum += rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID ? 1u : rayHit.hit.primID;
    }
    return checksum;
  }

 private:
  RTCDevice device_ = nullptr;  ///< owned
  RTCScene scene_ = nullptr;    ///< owned
};

/// The rank's share of the form-factor stage as run/formfactor_stage.cpp runs it (one
/// RowSampling, the rows in kPieces pieces appended to one tally, room reserved for them all
/// after the first), over every patch with state.range(0) threads. RADIOSITY_BENCH_PIECES=1
/// samples every row in one call instead.
const int64_t kPieces = std::stoll(fromEnvironment("RADIOSITY_BENCH_PIECES", "200"));

void BM_FormFactorStage(benchmark::State& state) {
  const Mesh& patches = benchPatches();
  const trace::SceneTracer& tracer = benchTracer();
  formfactor::Options options;
  options.raysPerPatch = kRaysPerPatch;
  options.seed = kSeed;
  options.threads = static_cast<int>(state.range(0));
  const int64_t n = patches.triangleCount(), pieces = std::min(n, kPieces);
  int64_t rays = 0;
  for (auto _ : state) {
    formfactor::Statistics statistics;
    formfactor::RowSampling sampling(tracer, patches, options);
    formfactor::SampleTally tally;
    for (int64_t p = 0; p < pieces; ++p) {
      sampling.sampleInto(tally, n * p / pieces, n * (p + 1) / pieces, 0, kRaysPerPatch,
                          statistics);
      formfactor::reserveRows(tally, n);
    }
    benchmark::DoNotOptimize(tally.sum.data());
    rays += statistics.raysCast;
    // The stage hands its rows on; freeing them is not its work (nor bare Embree's).
    state.PauseTiming();
    tally = {};
    state.ResumeTiming();
  }
  state.counters["rays/s"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

/// The same rays traced bare with rtcIntersect1, split into state.range(0) contiguous parts
/// (one thread each). Only the loop is timed; rays and scene are made beforehand.
void BM_BareEmbree(benchmark::State& state) {
  const RayBatch& rays = benchRays();
  static const BareScene scene(benchPatches());  // built once, as benchTracer()
  const int threads = static_cast<int>(state.range(0));
  std::vector<uint64_t> checksums(threads);
  int64_t traced = 0;
  for (auto _ : state) {
    auto part = [&](int t) {
      checksums[t] = scene.trace(rays, rays.size() * t / threads, rays.size() * (t + 1) / threads);
    };
    std::vector<std::thread> helpers;
    for (int t = 1; t < threads; ++t) helpers.emplace_back(part, t);
    part(0);
    for (std::thread& helper : helpers) helper.join();
    benchmark::DoNotOptimize(checksums.data());
    traced += rays.size();
  }
  state.counters["rays/s"] =
      benchmark::Counter(static_cast<double>(traced), benchmark::Counter::kIsRate);
}

/// The stage's tracing call alone on the same rays: trace::SceneTracer::intersect, one batch
/// of a row's rays at a time (Embree's stream API), split as BM_BareEmbree splits them. Between
/// the two: what the stream API costs against rtcIntersect1; between it and the stage: what
/// the stage adds around the tracing.
void BM_TracerBatches(benchmark::State& state) {
  const RayBatch& rays = benchRays();
  const trace::SceneTracer& tracer = benchTracer();
  const int threads = static_cast<int>(state.range(0));
  const int64_t rows = rays.size() / kRaysPerPatch;
  std::vector<uint64_t> checksums(threads);
  int64_t traced = 0;
  for (auto _ : state) {
    auto part = [&](int t) {
      trace::SceneTracer::RayBatch batch;
      trace::SceneTracer::HitBatch hits;
      batch.resize(kRaysPerPatch);
      uint64_t checksum = 0;
      for (int64_t row = rows * t / threads; row < rows * (t + 1) / threads; ++row) {
        for (int64_t k = 0; k < kRaysPerPatch; ++k) {
          const int64_t r = row * kRaysPerPatch + k;
          batch.set(k, {rays.origin[3 * r], rays.origin[3 * r + 1], rays.origin[3 * r + 2]},
                    {rays.direction[3 * r], rays.direction[3 * r + 1], rays.direction[3 * r + 2]},
                    std::numeric_limits<double>::infinity());
        }
        tracer.intersect(batch, hits);
        for (int64_t k = 0; k < kRaysPerPatch; ++k)
          checksum += hits.patch[k] < 0 ? 1u : static_cast<uint64_t>(hits.patch[k]);
      }
      checksums[t] = checksum;
    };
    std::vector<std::thread> helpers;
    for (int t = 1; t < threads; ++t) helpers.emplace_back(part, t);
    part(0);
    for (std::thread& helper : helpers) helper.join();
    benchmark::DoNotOptimize(checksums.data());
    traced += rows * kRaysPerPatch;
  }
  state.counters["rays/s"] =
      benchmark::Counter(static_cast<double>(traced), benchmark::Counter::kIsRate);
}

// Wall-clock time: with two threads CPU time of the main thread alone would say nothing.
BENCHMARK(BM_FormFactorStage)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BareEmbree)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TracerBatches)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace radiosity

BENCHMARK_MAIN();
