// MIS's light choice (formfactor/light_choice.h): emitter samples aimed at the lights a cluster's
// pilot saw. It must stay unbiased (the mean over seeds is the exact view factor), must not
// waste samples on lights a patch cannot see (the error is that of a scene without them), and
// must give the same rows on any split across threads, pieces and sample ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "analytic_view_factors.h"
#include "formfactor/emitter_set.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "test_scenes.h"

namespace radiosity::formfactor {
namespace {

// The unit emitter at z = 0 facing up and the unit receiver at z = 1 facing down, and, with
// `hiddenLights`, that many more emitters of 5 times its area in all, above the receiver and
// facing up: neither sees them, and uniform area sampling would spend 5/6 of its samples there.
Mesh receiverAndLights(int hiddenLights) {
  Mesh mesh = testing::parallelPlates(1, 1, 1);
  const double side = std::sqrt(5.0 / std::max(hiddenLights, 1));
  for (int k = 0; k < hiddenLights; ++k) {
    const double x = 3.0 * k;  // apart: each is a light of its own
    testing::addQuad(mesh, {x, 0, 3}, {x + side, 0, 3}, {x + side, side, 3}, {x, side, 3},
                     {0, 0, 0}, {1, 1, 1});
  }
  return partition::orderAlongCurve(partition::refine(mesh, 1.0 / 256));
}

// Per seed, the receiver's (the non-emitting patches') view factor to the emitting patches j
// with counted(j): Σ over receiver patches r of A_r F_rj, divided by the receiver's area.
template <class Counted>
std::vector<double> receiverTo(const Mesh& mesh, int64_t samples, int seeds, Counted counted) {
  SceneTracer tracer(mesh);
  std::vector<double> estimates;
  for (int seed = 1; seed <= seeds; ++seed) {
    Statistics s;
    const SparseRows rows =
        toFormFactors(sampleRows(tracer, mesh, 0, mesh.triangleCount(),
                                 {samples, uint64_t(seed), Estimator::kEmitterMis}, s));
    double weighted = 0, area = 0;
    for (int64_t i = 0; i < mesh.triangleCount(); ++i) {
      if (mesh.emission[i][0] > 0) continue;
      for (int64_t k = rows.rowStart[i]; k < rows.rowStart[i + 1]; ++k) {
        const int64_t j = rows.column[k];
        if (mesh.emission[j][0] > 0 && counted(j)) weighted += mesh.area(i) * rows.value[k];
      }
      area += mesh.area(i);
    }
    estimates.push_back(weighted / area);
  }
  return estimates;
}

// ... to the unit emitter below it (z = 0), not to the hidden lights.
std::vector<double> receiverToEmitter(const Mesh& mesh, int64_t samples, int seeds) {
  return receiverTo(mesh, samples, seeds, [&](int64_t j) { return mesh.corner(j, 0).z < 0.5; });
}

double mean(const std::vector<double>& x) {
  double sum = 0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

double rmsAround(const std::vector<double>& x, double exact) {
  double sum = 0;
  for (double v : x) sum += (v - exact) * (v - exact);
  return std::sqrt(sum / static_cast<double>(x.size()));
}

TEST(LightChoice, IsUnbiasedAndSpendsNoSamplesOnLightsThePatchCannotSee) {
  const double exact = testing::parallelRectangles(1, 1, 1);
  const int seeds = 64;
  const std::vector<double> alone = receiverToEmitter(receiverAndLights(0), 4, seeds);
  const std::vector<double> crowded = receiverToEmitter(receiverAndLights(20), 4, seeds);
  const double errorAlone = rmsAround(alone, exact), errorCrowded = rmsAround(crowded, exact);
  // Unbiased: the mean over seeds within 4 standard errors of the exact value.
  EXPECT_NEAR(mean(crowded), exact, 4 * errorCrowded / std::sqrt(double(seeds)));
  EXPECT_NEAR(mean(alone), exact, 4 * errorAlone / std::sqrt(double(seeds)));
  // Uniform over the emitters' area the crowded scene's error is 4.3 times that of the scene
  // alone (measured); the choice keeps it at 1.2–1.4 times (measured over four sets of seeds:
  // the by-area share's samples that go to the hidden lights, and the holes they leave in the
  // sequence's even spread).
  EXPECT_LT(errorCrowded, 2 * errorAlone) << errorAlone << " alone, " << errorCrowded;
}

// A ceiling of n × n small emitting squares above a unit receiver; with `gap` > 0 they are n²
// lights apart, with gap = 0 one light of touching squares (the same area).
Mesh receiverUnderTiles(int n, double gap) {
  Mesh mesh;
  testing::addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {0, 0, 0});
  auto at = [&](int k) { return -0.5 + 2.0 * k / n; };  // the same double for both neighbours
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const double x0 = at(a), y0 = at(b), x1 = at(a + 1) - gap, y1 = at(b + 1) - gap;
      testing::addQuad(mesh, {x0, y0, 1}, {x0, y1, 1}, {x1, y1, 1}, {x1, y0, 1}, {0, 0, 0},
                       {1, 1, 1});
    }
  }
  return partition::orderAlongCurve(partition::refine(mesh, 1.0 / 256));
}

// ... to all emitters.
std::vector<double> receiverToAllEmitters(const Mesh& mesh, int64_t samples, int seeds) {
  return receiverTo(mesh, samples, seeds, [](int64_t) { return true; });
}

// Among hundreds of small lights a pilot sees most once: the choice must then fall back to the
// area (Good–Turing's unseen share), or the lights the pilot missed would be starved.
TEST(LightChoice, ManySmallLightsCostNoMoreThanOneLightOfTheSameArea) {
  const int seeds = 64;
  const std::vector<double> one = receiverToAllEmitters(receiverUnderTiles(32, 0), 4, seeds);
  const std::vector<double> many = receiverToAllEmitters(receiverUnderTiles(32, 0.02), 4, seeds);
  const double spreadOne = rmsAround(one, mean(one)), spreadMany = rmsAround(many, mean(many));
  // Measured: 0.65 times; 1.25 times with the unseen share left at kByArea.
  EXPECT_LT(spreadMany, spreadOne) << spreadOne << " one light, " << spreadMany;
}

bool sameTally(const SampleTally& a, const SampleTally& b) {
  return a.firstRow == b.firstRow && a.samples == b.samples && a.rowStart == b.rowStart &&
         a.column == b.column && a.sum == b.sum;
}

// Every cluster's pilot is keyed by the seed and its patches alone: threads, pieces of rows and
// of samples give the rows of one call, bit for bit, in a scene of several lights (3 rooms).
TEST(LightChoice, RowsAreTheSameOnAnySplit) {
  const Mesh rooms = partition::orderAlongCurve(loadScene("builtin:rooms?patches=6000"));
  SceneTracer tracer(rooms);
  const int64_t n = rooms.triangleCount();
  const Options options{24, 7, Estimator::kEmitterMis, 0, 1};
  Statistics s;
  const SampleTally whole = sampleRows(tracer, rooms, 0, n, options, s);
  Options threaded = options;
  threaded.threads = 3;
  EXPECT_TRUE(sameTally(sampleRows(tracer, rooms, 0, n, threaded, s), whole));

  RowSampling sampling(tracer, rooms, threaded);
  const int64_t cut = n / 3 + 5;  // inside a cluster
  SampleTally joined;
  for (auto [first, end] : {std::pair<int64_t, int64_t>{0, cut}, {cut, n}}) {
    const SampleTally part =
        mergeSamples(sampling.sample(first, end, 0, 10, s), sampling.sample(first, end, 10, 14, s));
    for (int64_t r = 1; r <= part.rowCount(); ++r)
      joined.rowStart.push_back(static_cast<int64_t>(joined.column.size()) + part.rowStart[r]);
    joined.column.insert(joined.column.end(), part.column.begin(), part.column.end());
    joined.sum.insert(joined.sum.end(), part.sum.begin(), part.sum.end());
    joined.samples = part.samples;
  }
  EXPECT_TRUE(sameTally(joined, whole));
}

// Emitter draws are the inverse of the running area sums (the guide table only shortens the
// search): evenly spaced u1 put on every patch its share of the area to within one draw, over
// all emitters and within each light, for patches of areas 10^4 apart.
TEST(EmitterSet, EvenDrawsFallOnEveryPatchByItsArea) {
  Mesh rooms;  // squares of sides 1 to 0.01 (a light each, or a few unit ones touching)
  for (int k = 0; k < 1200; ++k) {
    const double side = std::pow(10.0, -2.0 * (k % 7) / 6), x = k % 40, y = 2.0 * (k / 40);
    testing::addQuad(rooms, {x, y, 0}, {x + side, y, 0}, {x + side, y + side, 0}, {x, y + side, 0},
                     {0.5, 0.5, 0.5}, {1, 1, 1});
  }
  for (int64_t t = 0; t < rooms.triangleCount(); t += 5) rooms.emission[t] = Rgb{0, 0, 0};
  const EmitterSet emitters(rooms);
  ASSERT_GT(emitters.lightCount(), 1);
  const int64_t draws = 40 * rooms.triangleCount();
  std::vector<int64_t> count(rooms.triangleCount(), 0);
  for (int64_t k = 0; k < draws; ++k)
    ++count[emitters.sample((k + 0.5) / static_cast<double>(draws), 0.3, 0.3).patch];
  double smallest = 1e300, largest = 0;
  for (int64_t t = 0; t < rooms.triangleCount(); ++t) {
    const double expected =
        t % 5 == 0 ? 0 : static_cast<double>(draws) * rooms.area(t) / emitters.totalArea();
    ASSERT_NEAR(count[t], expected, 1.0) << "patch " << t;
    if (t % 5 != 0)
      smallest = std::min(smallest, rooms.area(t)), largest = std::max(largest, rooms.area(t));
  }
  EXPECT_GT(largest / smallest, 1e3);
  for (int64_t light : {int64_t{0}, emitters.lightCount() / 2, emitters.lightCount() - 1}) {
    std::fill(count.begin(), count.end(), 0);
    const int64_t lightDraws = 20000;
    for (int64_t k = 0; k < lightDraws; ++k)
      ++count[emitters.sampleLight(light, (k + 0.5) / static_cast<double>(lightDraws), 0.3, 0.3)
                  .patch];
    for (int64_t t = 0; t < rooms.triangleCount(); ++t) {
      const bool inLight = t % 5 != 0 && emitters.lightOf(t) == light;
      const double expected =
          inLight ? static_cast<double>(lightDraws) * rooms.area(t) / emitters.lightArea(light) : 0;
      ASSERT_NEAR(count[t], expected, 1.0) << "light " << light << ", patch " << t;
    }
  }
}

}  // namespace
}  // namespace radiosity::formfactor
