// Error of each form-factor estimator against rays, on cases with known answers:
//  - the unit plates at distance 1 (F = 0.19982, Howell C-11): RMS error of F over 32 seeds;
//  - the Cornell box floor: RMS error of direct irradiance Σ_emitters F_ij E_j over the floor
//    patches relative to their mean, against a reference of 16384 MIS samples per patch (a
//    per-patch relative error would be ruled by the patches in half shadow).
// Equal rays: MIS casts two rays per sample, so it is given half the samples.
// Usage: build/bench/estimator_error
#include <cmath>
#include <cstdio>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "tests/cornell_floor_light.h"
#include "tests/sampled_form_factors.h"

namespace radiosity {
namespace {

using formfactor::Estimator;

double platesRmsError(int64_t rays, Estimator estimator) {
  const Mesh plates = loadScene("builtin:plates");
  const trace::SceneTracer tracer(plates);
  const double exact = 0.19982489569838746;
  const int64_t samples = estimator == Estimator::kEmitterMis ? rays / 2 : rays;
  double squares = 0;
  const int seeds = 32;
  for (int seed = 1; seed <= seeds; ++seed) {
    formfactor::Statistics s;
    // Triangles 2 and 3 are the receiver (builtin:plates adds the emitter first).
    const formfactor::SparseRows rows =
        testing::sampledFormFactors(tracer, plates, 2, 4, {samples, uint64_t(seed), estimator}, s);
    double estimate = 0;
    for (int64_t k = 0; k < rows.nonzeros(); ++k) estimate += 0.5 * rows.value[k];
    squares += (estimate - exact) * (estimate - exact);
  }
  return std::sqrt(squares / seeds);
}

}  // namespace
}  // namespace radiosity

int main() {
  using namespace radiosity;
  std::printf("plates: RMS error of F (exact 0.19982) over 32 seeds\n%8s %12s %12s\n", "rays",
              "hemisphere", "mis");
  for (int64_t rays : {16, 64, 256, 1024, 4096}) {
    std::printf("%8lld %12.5f %12.5f\n", static_cast<long long>(rays),
                platesRmsError(rays, Estimator::kHemisphere),
                platesRmsError(rays, Estimator::kEmitterMis));
  }

  const Mesh cornell = partition::refine(loadScene("builtin:cornell"), 4000);
  const trace::SceneTracer tracer(cornell);
  const std::vector<int64_t> floor = testing::cornellFloor(cornell);
  const auto reference =
      testing::floorDirectIrradiance(cornell, tracer, floor, 16384, Estimator::kEmitterMis, 12345);
  std::printf(
      "\nCornell floor (%zu patches): RMS error of direct irradiance / its mean\n%8s %12s %12s\n",
      floor.size(), "rays", "hemisphere", "mis");
  for (int64_t rays : {64, 256, 1024, 4096}) {
    const auto hemisphere =
        testing::floorDirectIrradiance(cornell, tracer, floor, rays, Estimator::kHemisphere, 1);
    const auto mis =
        testing::floorDirectIrradiance(cornell, tracer, floor, rays / 2, Estimator::kEmitterMis, 1);
    std::printf("%8lld %12.4f %12.4f\n", static_cast<long long>(rays),
                testing::rmsErrorOverMean(hemisphere, reference),
                testing::rmsErrorOverMean(mis, reference));
  }
  return 0;
}
