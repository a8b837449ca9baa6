// The hierarchical transport across ranks (hierarchy/block_transport.h): each rank holds its
// block of rows and the links its own rows made, and together they give the serial transport of
// all rows' links, bit for bit on one rank and to round-off on any other count, with blocks cut
// anywhere; the power a uniform B sends is kept. Runs on 1 rank (the discovered tests) and whole
// on 2 and 3 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <memory>
#include <vector>

#include "formfactor/formfactor.h"
#include "hierarchy/block_transport.h"
#include "hierarchy/hierarchy.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "petsc_environment.h"
#include "solve/hierarchical_solve.h"
#include "solve_fixture.h"

namespace radiosity::hierarchy {
namespace {

[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(
        new testing::PetscEnvironment({"hierarchy_transport_test"}));

struct Scene {
  Mesh patches;
  std::unique_ptr<trace::SceneTracer> tracer;
  formfactor::Options options;
};

Scene cornell() {
  Scene s;
  Mesh scene = loadScene("builtin:cornell");
  s.patches = partition::orderAlongCurve(partition::refine(scene, scene.totalArea() / 700));
  normaliseForTracing(s.patches);
  s.tracer = std::make_unique<trace::SceneTracer>(s.patches);
  s.options.raysPerPatch = 64;
  s.options.seed = 3;
  s.options.estimator = formfactor::Estimator::kEmitterMis;
  return s;
}

SampleTally rows(const Scene& s, partition::PatchRange range) {
  formfactor::RowSampling sampling(*s.tracer, s.patches, s.options);
  formfactor::Statistics statistics;
  return sampling.sample(range.begin, range.end, 0, s.options.raysPerPatch, statistics);
}

// Receivers and sources grouped, some receivers kept apart as by probes.
LinkOracle oracle() {
  LinkOracle o;
  o.spread = 0.5;
  o.seesWhole = [](const ClusterNode& r, const ClusterNode& s) { return (r.begin + s.end) % 4; };
  return o;
}

std::vector<double> varied(int64_t n) {
  std::vector<double> x(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) x[i] = 1 + std::sin(static_cast<double>(i));
  return x;
}

// This rank's transport of x over its block `owned`, from the links of its own rows as the tally
// keeps them.
std::vector<double> acrossRanks(const Scene& s, const PatchTree& tree, partition::PatchRange owned,
                                Push push, const std::vector<double>& x) {
  LinkTally tally(tree, oracle());
  tally.add(rows(s, owned));
  std::unique_ptr<BlockTransport> transport;
  EXPECT_EQ(BlockTransport::create(MPI_COMM_WORLD, tree, owned, tally, push, &transport), 0);
  std::vector<double> y(static_cast<size_t>(owned.size()));
  EXPECT_EQ(transport->apply(x.data() + owned.begin, y.data()), 0);
  EXPECT_EQ(transport->apply(x.data() + owned.begin, y.data()), 0);  // (twice: nothing left over)
  return y;
}

// Blocks cut as the program does (by count), and cut unevenly: the first rank's a seventh.
partition::PatchRange unevenBlock(int64_t n) {
  const int rank = testing::rank(), ranks = testing::ranks();
  if (ranks == 1) return {0, n};
  const int64_t first = n / 7;
  if (rank == 0) return {0, first};
  const partition::PatchRange rest = partition::blockOf(n - first, rank - 1, ranks - 1);
  return {first + rest.begin, first + rest.end};
}

// Blocks where the second rank holds no patch at all (more ranks than work).
partition::PatchRange blockWithAnEmptyRank(int64_t n) {
  const int rank = testing::rank(), ranks = testing::ranks();
  if (ranks == 1) return {0, n};
  if (rank == 1) {
    const int64_t at = partition::blockOf(n, 0, ranks - 1).end;
    return {at, at};
  }
  return partition::blockOf(n, rank == 0 ? 0 : rank - 1, ranks - 1);
}

TEST(BlockTransport, GivesTheSerialTransportOnAnyRankCount) {
  const Scene s = cornell();
  const PatchTree tree(s.patches);
  const int64_t n = s.patches.triangleCount();
  const Links all = linksFromRows(tree, oracle(), rows(s, {0, n}));
  const std::vector<double> x = varied(n);
  for (const Push push : {Push::kUniform, Push::kLinear}) {
    const std::vector<double> serial = transport(tree, all, x, push);
    for (const partition::PatchRange owned :
         {partition::blockOf(n, testing::rank(), testing::ranks()), unevenBlock(n),
          blockWithAnEmptyRank(n)}) {
      const std::vector<double> y = acrossRanks(s, tree, owned, push, x);
      for (int64_t p = 0; p < owned.size(); ++p) {
        if (testing::ranks() == 1) {
          ASSERT_EQ(y[p], serial[owned.begin + p]) << p;  // the same sums in the same order
        } else {
          ASSERT_NEAR(y[p], serial[owned.begin + p], 1e-13 * std::abs(serial[owned.begin + p]))
              << "patch " << owned.begin + p;
        }
      }
    }
  }
}

// Blocks that leave a patch out are refused, on every rank alike (PETSc's error, not a hang).
TEST(BlockTransport, RefusesBlocksThatDoNotTileThePatches) {
  const Scene s = cornell();
  const PatchTree tree(s.patches);
  const int64_t n = s.patches.triangleCount();
  const partition::PatchRange owned = partition::blockOf(n - 1, testing::rank(), testing::ranks());
  std::unique_ptr<BlockTransport> transport;
  // (the error handed back, not traced: the traceback handler stops every rank but the first)
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode code =
      BlockTransport::create(MPI_COMM_WORLD, tree, owned, Links{}, Push::kUniform, &transport);
  PetscPopErrorHandler();
  EXPECT_EQ(code, PETSC_ERR_ARG_INCOMP);
  EXPECT_EQ(transport, nullptr);
}

// Three vectors interleaved patch by patch are transported as each alone, bit for bit.
TEST(BlockTransport, TransportsInterleavedComponentsAsEachAlone) {
  const Scene s = cornell();
  const PatchTree tree(s.patches);
  const int64_t n = s.patches.triangleCount();
  const partition::PatchRange owned = unevenBlock(n);
  LinkTally tally(tree, oracle());
  tally.add(rows(s, owned));
  std::unique_ptr<BlockTransport> transport;
  ASSERT_EQ(
      BlockTransport::create(MPI_COMM_WORLD, tree, owned, tally.links(), Push::kLinear, &transport),
      0);
  const std::vector<double> x = varied(3 * owned.size());
  std::vector<double> y(x.size());
  ASSERT_EQ(transport->apply(x.data(), y.data(), 3), 0);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> one(static_cast<size_t>(owned.size())), alone(one.size());
    for (int64_t p = 0; p < owned.size(); ++p) one[p] = x[3 * p + c];
    ASSERT_EQ(transport->apply(one.data(), alone.data()), 0);
    for (int64_t p = 0; p < owned.size(); ++p) ASSERT_EQ(y[3 * p + c], alone[p]) << p;
  }
}

// A uniform B of 1: the links send each receiver node the area-mean of its rows' sums over the
// source, so the power arriving, Σ A_i H_i, is the flat F's, Σ A_i Σ_j F_ij, through any mix of
// link levels and either push.
TEST(BlockTransport, KeepsThePowerOfAUniformRadiosity) {
  const Scene s = cornell();
  const PatchTree tree(s.patches);
  const int64_t n = s.patches.triangleCount();
  const partition::PatchRange owned = unevenBlock(n);
  const SampleTally own = rows(s, owned);
  double flat = 0;
  for (int64_t row = 0; row < own.rowCount(); ++row)
    for (int64_t k = own.rowStart[row]; k < own.rowStart[row + 1]; ++k)
      flat += s.patches.area(owned.begin + row) * static_cast<double>(own.sum[k]) /
              (0x1p32 * static_cast<double>(own.samples));
  MPI_Allreduce(MPI_IN_PLACE, &flat, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const std::vector<double> one(static_cast<size_t>(n), 1.0);
  for (const Push push : {Push::kUniform, Push::kLinear}) {
    const std::vector<double> y = acrossRanks(s, tree, owned, push, one);
    double power = 0;
    for (int64_t p = 0; p < owned.size(); ++p) power += s.patches.area(owned.begin + p) * y[p];
    MPI_Allreduce(MPI_IN_PLACE, &power, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_NEAR(power, flat, 1e-12 * flat);
  }
}

// B = b + ρ ∘ T B (b = E + ρ ∘ (D − T E)) by Jacobi on one process, every row's links at once.
std::vector<Rgb> serialSolve(const Mesh& patches, const PatchTree& tree, const Links& links,
                             const std::vector<Rgb>& direct) {
  const int64_t n = patches.triangleCount();
  std::vector<Rgb> b(static_cast<size_t>(n));
  for (int c = 0; c < 3; ++c) {
    std::vector<double> e(n), x(n), rhs(n);
    for (int64_t i = 0; i < n; ++i) e[i] = patches.emission[i][c];
    const std::vector<double> te = transport(tree, links, e, Push::kLinear);
    for (int64_t i = 0; i < n; ++i)
      x[i] = rhs[i] = e[i] + patches.reflectance[i][c] * (direct[i][c] - te[i]);
    for (int iteration = 0; iteration < 500; ++iteration) {
      const std::vector<double> tx = transport(tree, links, x, Push::kLinear);
      for (int64_t i = 0; i < n; ++i) x[i] = rhs[i] + patches.reflectance[i][c] * tx[i];
    }
    for (int64_t i = 0; i < n; ++i) b[i][c] = x[i];
  }
  return b;
}

// The flat F's B = E + ρ ∘ F B from the same rows, by Jacobi.
std::vector<Rgb> flatSolve(const Mesh& patches, const SampleTally& all) {
  const formfactor::SparseRows f = formfactor::toFormFactors(all);
  const int64_t n = patches.triangleCount();
  std::vector<Rgb> b(patches.emission);
  for (int iteration = 0; iteration < 500; ++iteration) {
    std::vector<Rgb> next(patches.emission);
    for (int64_t i = 0; i < n; ++i)
      for (int64_t k = f.rowStart[i]; k < f.rowStart[i + 1]; ++k)
        for (int c = 0; c < 3; ++c)
          next[i][c] += patches.reflectance[i][c] * f.value[k] * b[f.column[k]][c];
    b = next;
  }
  return b;
}

// The solve across ranks gives the serial answer of all rows' links on any rank count and block
// cut, and the hierarchy's approximation stays small: the same rows' flat F gives B within 2 %
// on the reflected light (area-weighted, over the patches that do not emit).
TEST(HierarchicalSolve, GivesTheSerialAnswerAndNearlyTheFlatFs) {
  const Scene s = cornell();
  const PatchTree tree(s.patches);
  const int64_t n = s.patches.triangleCount();
  LinkOracle probed;
  probed.spread = 0.4;
  VisibilityProbe probe(*s.tracer, s.patches);
  probed.seesWhole = probe.asOracle();
  const SampleTally all = rows(s, {0, n});
  LinkedRows everyRow(tree, probed, s.patches, {0, n});
  everyRow.add(all);
  const std::vector<Rgb> serial = serialSolve(s.patches, tree, everyRow.links(), everyRow.direct());
  const std::vector<Rgb> flat = flatSolve(s.patches, all);
  const partition::PatchRange owned = unevenBlock(n);
  LinkedRows mine(tree, probed, s.patches, owned);
  mine.add(rows(s, owned));
  std::unique_ptr<BlockTransport> transport;
  ASSERT_EQ(
      BlockTransport::create(MPI_COMM_WORLD, tree, owned, mine.links(), Push::kLinear, &transport),
      0);
  const std::vector<Rgb> rho(s.patches.reflectance.begin() + owned.begin,
                             s.patches.reflectance.begin() + owned.end);
  const std::vector<Rgb> e(s.patches.emission.begin() + owned.begin,
                           s.patches.emission.begin() + owned.end);
  const solve::HierarchicalSystem system{*transport, rho, e, mine.direct()};
  solve::HierarchicalSolution solution;
  ASSERT_EQ(solve::solveHierarchical(MPI_COMM_WORLD, system, 1e-13, &solution), 0);
  double gap = 0, light = 0;
  for (int64_t p = 0; p < owned.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double b = solution.radiosity[p][c], expected = serial[owned.begin + p][c];
      ASSERT_NEAR(b, expected, 1e-10 * std::max(1.0, std::abs(expected))) << owned.begin + p;
      if (e[p][c] > 0) continue;
      const double area = s.patches.area(owned.begin + p);
      gap += area * std::abs(b - flat[owned.begin + p][c]);
      light += area * flat[owned.begin + p][c];
    }
  MPI_Allreduce(MPI_IN_PLACE, &gap, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &light, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_LT(gap / light, 0.02);
  EXPECT_GT(gap / light, 0);  // (the links do approximate)
  RecordProperty("gap", std::to_string(gap / light));
  if (testing::rank() == 0) std::printf("hierarchical against flat: %.4f\n", gap / light);
}

}  // namespace
}  // namespace radiosity::hierarchy
