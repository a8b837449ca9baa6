// F's one store in single precision (SplitRows::singlePrecision) and the shell matrix the solve
// multiplies by (solve/single_precision_matrix.h): it must act exactly as PETSc's AIJ matrix of
// the same rounded values, give back the tally a checkpoint writes and a restart reads without
// drifting, and move B by no more than the rounding's bound. Runs on 1 rank (the discovered
// tests) and whole on 2 and 3 ranks: each rank holds its block of rows as in the program.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "petsc_environment.h"
#include "petsc_vectors.h"
#include "sampled_form_factors.h"
#include "solve/assemble.h"
#include "solve/single_precision_matrix.h"
#include "solve/solve.h"
#include "solve_fixture.h"

namespace radiosity {
namespace {

[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new testing::PetscEnvironment({"single_precision_test"}));

// The Cornell box's patches and this rank's rows of F, sampled into a store as the form-factor
// stage fills it (pieces of 37 rows), in single or double precision.
struct Sampled {
  Mesh patches;
  partition::PatchRange owned;
  formfactor::SplitRows store;
};

Sampled sampleCornell(bool single, int64_t rays = 64) {
  Sampled s;
  Mesh scene = loadScene("builtin:cornell");
  s.patches = partition::orderAlongCurve(partition::refine(scene, scene.totalArea() / 600));
  s.owned = partition::blockOf(s.patches.triangleCount(), testing::rank(), testing::ranks());
  formfactor::Options options;
  options.raysPerPatch = rays;
  options.seed = 7;
  options.estimator = formfactor::Estimator::kEmitterMis;  // (sums that are not whole hits)
  s.store.singlePrecision = single;
  testing::sampleIntoStore(trace::SceneTracer(s.patches), s.patches, s.owned, options, s.store);
  return s;
}

using testing::entries;

// x_i = 1 + sin(global index): no two entries alike, so a column taken for another shows.
void fillVaried(Vec x) {
  PetscInt first, end;
  PetscScalar* a;
  ASSERT_EQ(VecGetOwnershipRange(x, &first, &end), 0);
  ASSERT_EQ(VecGetArray(x, &a), 0);
  for (PetscInt i = first; i < end; ++i) a[i - first] = 1 + std::sin(static_cast<double>(i));
  ASSERT_EQ(VecRestoreArray(x, &a), 0);
}

TEST(SinglePrecisionStore, ItsMatrixActsAsTheAijMatrixOfItsRoundedValues) {
  Sampled s = sampleCornell(true);
  const formfactor::SparseRows before = formfactor::toFormFactors(s.store);
  for (size_t k = 0; k < before.value.size(); ++k)  // every value is a float's
    ASSERT_EQ(before.value[k], static_cast<double>(static_cast<float>(before.value[k])));
  Mat aij, shell;
  ASSERT_EQ(solve::assembleRows(PETSC_COMM_WORLD, before, nullptr, &aij), 0);
  ASSERT_EQ(solve::createSinglePrecisionMatrix(PETSC_COMM_WORLD, s.store, {}, &shell), 0);
  EXPECT_TRUE(solve::isSinglePrecisionMatrix(shell));
  EXPECT_FALSE(solve::isSinglePrecisionMatrix(aij));

  // Products, one channel and three interleaved (PETSc's MAIJ against ours), bit for bit: the
  // same values summed in the same order (the rank's own columns, then the others).
  for (PetscInt k : {1, 3}) {
    Mat a = aij, b = shell, aBlock = nullptr, bBlock = nullptr;
    if (k > 1) {
      ASSERT_EQ(MatCreateMAIJ(aij, k, &aBlock), 0);
      ASSERT_EQ(solve::createSinglePrecisionComponents(shell, k, &bBlock), 0);
      a = aBlock;
      b = bBlock;
    }
    Vec x, ya, yb;
    ASSERT_EQ(MatCreateVecs(a, &x, &ya), 0);
    ASSERT_EQ(VecDuplicate(ya, &yb), 0);
    fillVaried(x);
    ASSERT_EQ(MatMult(a, x, ya), 0);
    ASSERT_EQ(MatMult(b, x, yb), 0);
    EXPECT_EQ(entries(ya), entries(yb)) << k << " channels";
    // The diagonal (MAIJ has none to give: the one-channel AIJ's, k times over).
    Vec d;
    ASSERT_EQ(MatCreateVecs(aij, nullptr, &d), 0);
    ASSERT_EQ(MatGetDiagonal(aij, d), 0);
    ASSERT_EQ(MatGetDiagonal(b, yb), 0);
    std::vector<PetscScalar> repeated;
    for (PetscScalar v : entries(d)) repeated.insert(repeated.end(), k, v);
    EXPECT_EQ(repeated, entries(yb)) << k << " channels";
    ASSERT_EQ(VecDestroy(&d), 0);
    for (Vec* v : {&x, &ya, &yb}) ASSERT_EQ(VecDestroy(v), 0);
    for (Mat* m : {&aBlock, &bBlock}) ASSERT_EQ(MatDestroy(m), 0);
  }
  // Rows, row maxima and the nonzeros the solve counts its work by.
  PetscInt first, end;
  ASSERT_EQ(MatGetOwnershipRange(shell, &first, &end), 0);
  ASSERT_EQ(first, s.owned.begin);
  for (PetscInt row = first; row < end; ++row) {
    PetscInt n1, n2;
    const PetscInt *c1, *c2;
    const PetscScalar *v1, *v2;
    ASSERT_EQ(MatGetRow(aij, row, &n1, &c1, &v1), 0);
    ASSERT_EQ(MatGetRow(shell, row, &n2, &c2, &v2), 0);
    ASSERT_EQ(std::vector<PetscInt>(c1, c1 + n1), std::vector<PetscInt>(c2, c2 + n2)) << row;
    ASSERT_EQ(std::vector<PetscScalar>(v1, v1 + n1), std::vector<PetscScalar>(v2, v2 + n2));
    ASSERT_EQ(MatRestoreRow(shell, row, &n2, &c2, &v2), 0);
    ASSERT_EQ(MatRestoreRow(aij, row, &n1, &c1, &v1), 0);
  }
  Vec ma, mb;
  ASSERT_EQ(MatCreateVecs(aij, nullptr, &ma), 0);
  ASSERT_EQ(VecDuplicate(ma, &mb), 0);
  ASSERT_EQ(MatGetRowMaxAbs(aij, ma, nullptr), 0);
  ASSERT_EQ(MatGetRowMaxAbs(shell, mb, nullptr), 0);
  EXPECT_EQ(entries(ma), entries(mb));
  ASSERT_EQ(VecDestroy(&ma), 0);
  ASSERT_EQ(VecDestroy(&mb), 0);
  MatInfo infoA, infoB;
  ASSERT_EQ(MatGetInfo(aij, MAT_GLOBAL_SUM, &infoA), 0);
  ASSERT_EQ(MatGetInfo(shell, MAT_GLOBAL_SUM, &infoB), 0);
  EXPECT_EQ(infoA.nz_used, infoB.nz_used);

  // While the shell holds the store its off-diagonal columns are numbered compactly; the store
  // still reads as before, and takeRowsBack gives the global ids back.
  EXPECT_EQ(formfactor::toFormFactors(s.store).column, before.column);
  ASSERT_EQ(solve::takeRowsBack(&shell, s.store), 0);
  const formfactor::SparseRows after = formfactor::toFormFactors(s.store);
  EXPECT_EQ(after.column, before.column);
  EXPECT_EQ(after.value, before.value);
  ASSERT_EQ(MatDestroy(&aij), 0);
}

// A checkpoint writes the tally rebuilt from the floats and a restart appends it again: that
// must give the same floats (else a run stopped and resumed would drift from one that was not),
// and the rebuilt sums must be the sampled ones to the rounding.
TEST(SinglePrecisionStore, ItsTallyIsAFixedPointThroughACheckpoint) {
  const Sampled single = sampleCornell(true), exact = sampleCornell(false);
  const formfactor::SampleTally rebuilt = single.store.tally(0, single.store.rowCount());
  const formfactor::SampleTally sampled = exact.store.tally(0, exact.store.rowCount());
  ASSERT_EQ(rebuilt.column, sampled.column);
  ASSERT_FALSE(rebuilt.sum.empty());
  for (size_t k = 0; k < rebuilt.sum.size(); ++k)
    ASSERT_LE(std::abs(static_cast<double>(rebuilt.sum[k] - sampled.sum[k])),
              0x1p-24 * static_cast<double>(sampled.sum[k]) + 1)
        << k;
  formfactor::SplitRows again;
  again.firstRow = single.store.firstRow;
  again.endRow = single.store.endRow;
  again.singlePrecision = true;
  formfactor::appendRows(again, rebuilt);
  EXPECT_EQ(formfactor::toFormFactors(again).value, formfactor::toFormFactors(single.store).value);
  EXPECT_EQ(again.tally(0, again.rowCount()).sum, rebuilt.sum);
}

// B from the single-precision store moves by less than the rounding's bound, 2^-24 / (1 − ρ_max)
// of itself, from B of the double one (the same rays), on every patch that reflects light.
TEST(SinglePrecisionStore, MovesBByLessThanItsBound) {
  LocalSolution solutions[2];
  double largestReflectance = 0;
  for (bool single : {false, true}) {
    Sampled s = sampleCornell(single);
    std::vector<Rgb> reflectance, emission;
    std::vector<double> area;
    for (int64_t i = s.owned.begin; i < s.owned.end; ++i) {
      reflectance.push_back(s.patches.reflectance[i]);
      emission.push_back(s.patches.emission[i]);
      area.push_back(s.patches.area(i));
      for (double rho : s.patches.reflectance[i])
        largestReflectance = std::max(largestReflectance, rho);
    }
    solve::Options options;
    options.rtol = 1e-13;
    options.samplesPerRow = 0;  // (no error estimate: the products alone are compared)
    solve::Report report;
    solutions[single ? 1 : 0] = solve::solveRadiosity(std::move(s.store), s.patches.triangleCount(),
                                                      reflectance, emission, area, options, report);
  }
  const double bound = 0x1p-24 / (1 - largestReflectance);
  double moved = 0;
  for (size_t i = 0; i < solutions[0].radiosity.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double b = solutions[0].radiosity[i][c];
      if (b > 0) moved = std::max(moved, std::abs(solutions[1].radiosity[i][c] - b) / b);
    }
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_GT(moved, 0);  // (the values were rounded: the test compares two different F)
  EXPECT_LT(moved, bound) << "bound " << bound;
}

TEST(SinglePrecisionStore, ServesWhereItsRoundingIsFarBelowTheSamplingError) {
  EXPECT_TRUE(formfactor::singlePrecisionServes(32, 0.8));
  EXPECT_TRUE(formfactor::singlePrecisionServes(1024, 0.95));
  EXPECT_FALSE(formfactor::singlePrecisionServes(1024, 0.99999));
  EXPECT_FALSE(formfactor::singlePrecisionServes(1024, 1.0));
  EXPECT_FALSE(formfactor::singlePrecisionServes(1024, std::nan("")));
  EXPECT_FALSE(formfactor::singlePrecisionServes(1 << 18, 0.5));  // sums kept besides
  EXPECT_FALSE(formfactor::singlePrecisionServes(200000, 0.8));
  // Exact rows keep their sums on floats: from kSingleExactRowsPatches patches on.
  EXPECT_TRUE(
      formfactor::singlePrecisionServesExactRows(formfactor::kSingleExactRowsPatches, 1024));
  EXPECT_FALSE(
      formfactor::singlePrecisionServesExactRows(formfactor::kSingleExactRowsPatches - 1, 1024));
  EXPECT_FALSE(formfactor::singlePrecisionServesExactRows(20000, 1 << 18));
}

}  // namespace
}  // namespace radiosity
