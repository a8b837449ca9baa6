// Exact rows stored once a pair (SplitRows::pairsOnce) and the shell the solve multiplies by:
// each row holds the pairs it owns (formfactor::ownsPair) and, as its diagonal entry, the sum of
// the others; the shell is F with each stored F_ij's mirror F_ji = F_ij A_i / A_j and F_ii the
// row's rest less its mirrors' sum. Checked against that F written out whole in the test (every
// rank gathers every row): the product (one channel and three), the diagonal, the row maxima and
// the nonzeros, and each row's sum, which must stay the whole row's. Runs on 1 rank (the
// discovered tests) and whole on 2 and 3 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "petsc_environment.h"
#include "petsc_vectors.h"
#include "sampled_form_factors.h"
#include "solve/single_precision_matrix.h"
#include "solve_fixture.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new testing::PetscEnvironment({"pairs_once_test"}));

// A closed box of unequal faces (so that A_i / A_j varies), this rank's exact rows on floats,
// whole or once a pair.
struct Rows {
  Mesh patches;
  partition::PatchRange owned;
  formfactor::SplitRows store;
  std::vector<double> area;  ///< this rank's rows'
};

Rows exactRows(bool pairsOnce) {
  Rows s;
  Mesh box = testing::closedBox(0.5, 1, 1.0);
  for (Vec3& v : box.vertices) v[0] *= 1.7;  // (a box, not a cube: patches of two sizes)
  s.patches = partition::orderAlongCurve(partition::refine(box, 0.02));
  s.owned = partition::blockOf(s.patches.triangleCount(), testing::rank(), testing::ranks());
  formfactor::Options options;
  options.raysPerPatch = 16;
  options.exactRows = true;
  options.singlePrecision = true;
  options.pairsOnce = pairsOnce;
  s.store.singlePrecision = true;
  s.store.pairsOnce = pairsOnce;
  testing::sampleIntoStore(trace::SceneTracer(s.patches), s.patches, s.owned, options, s.store);
  for (int64_t i = s.owned.begin; i < s.owned.end; ++i) s.area.push_back(s.patches.area(i));
  return s;
}

// The F the shell stands for, dense, from every rank's stored rows (gathered): stored F_ij,
// their mirrors, and F_ii = rest − mirrors' sum.
std::vector<double> wholeF(const Rows& s) {
  const int64_t n = s.patches.triangleCount();
  std::vector<double> f(static_cast<size_t>(n * n), 0.0), rest(static_cast<size_t>(n), 0.0);
  const formfactor::SampleTally mine = s.store.tally(0, s.store.rowCount());
  for (int64_t r = 0; r < mine.rowCount(); ++r)
    for (int64_t k = mine.rowStart[r]; k < mine.rowStart[r + 1]; ++k) {
      const int64_t i = mine.firstRow + r, j = mine.column[k];
      const double value = static_cast<double>(mine.sum[k]) / (0x1p32 * mine.samples);
      if (i == j) {
        rest[i] = value;
      } else {
        f[i * n + j] = value;
        f[j * n + i] = value * s.patches.area(i) / s.patches.area(j);
      }
    }
  MPI_Allreduce(MPI_IN_PLACE, f.data(), static_cast<int>(f.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, rest.data(), static_cast<int>(rest.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  for (int64_t i = 0; i < n; ++i) {
    double mirrors = 0;
    for (int64_t j = 0; j < n; ++j)
      if (j != i && !formfactor::ownsPair(i, j)) mirrors += f[i * n + j];
    f[i * n + i] = rest[i] - mirrors;
  }
  return f;
}

using testing::entries;

double varied(int64_t i, int c) { return 1 + std::sin(static_cast<double>(3 * i + c)); }

TEST(PairsOnce, EachRowKeepsHalfItsPairsAndItsWholeSum) {
  const Rows pairs = exactRows(true), whole = exactRows(false);
  int64_t counts[2] = {pairs.store.entries, whole.store.entries};
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_LT(counts[0], 0.52 * static_cast<double>(counts[1]));
  EXPECT_GT(counts[0], 0.48 * static_cast<double>(counts[1]));
  // A row's stored entries (its rest among them) add up to what the whole row adds up to.
  const std::vector<double> a = formfactor::rowSums(pairs.store),
                            b = formfactor::rowSums(whole.store);
  ASSERT_EQ(a.size(), b.size());
  for (size_t r = 0; r < a.size(); ++r) EXPECT_EQ(a[r], b[r]) << r;
  // The stored pairs are the whole rows' own entries.
  const formfactor::SampleTally p = pairs.store.tally(0, pairs.store.rowCount());
  const formfactor::SampleTally w = whole.store.tally(0, whole.store.rowCount());
  for (int64_t r = 0; r < p.rowCount(); ++r)
    for (int64_t k = p.rowStart[r]; k < p.rowStart[r + 1]; ++k) {
      const int64_t i = p.firstRow + r, j = p.column[k];
      if (i == j) continue;
      EXPECT_TRUE(formfactor::ownsPair(i, j));
      const auto* at =
          std::find(w.column.data() + w.rowStart[r], w.column.data() + w.rowStart[r + 1], j);
      ASSERT_NE(at, w.column.data() + w.rowStart[r + 1]);
      EXPECT_EQ(p.sum[k], w.sum[static_cast<size_t>(at - w.column.data())]);
    }
}

TEST(PairsOnce, TheShellIsTheWholeFOfThePairs) {
  Rows s = exactRows(true);
  const std::vector<double> f = wholeF(s);
  const int64_t n = s.patches.triangleCount(), first = s.owned.begin, end = s.owned.end;
  Mat shell;
  ASSERT_EQ(solve::createSinglePrecisionMatrix(PETSC_COMM_WORLD, s.store, s.area, &shell), 0);
  EXPECT_TRUE(solve::holdsPairsOnce(shell));
  for (PetscInt k : {1, 3}) {
    Mat m = shell, block = nullptr;
    if (k > 1) {
      ASSERT_EQ(solve::createSinglePrecisionComponents(shell, k, &block), 0);
      m = block;
    }
    Vec x, y;
    ASSERT_EQ(MatCreateVecs(m, &x, &y), 0);
    PetscScalar* xa;
    ASSERT_EQ(VecGetArray(x, &xa), 0);
    for (int64_t i = first; i < end; ++i)
      for (int c = 0; c < k; ++c) xa[(i - first) * k + c] = varied(i, c);
    ASSERT_EQ(VecRestoreArray(x, &xa), 0);
    ASSERT_EQ(MatMult(m, x, y), 0);
    const std::vector<PetscScalar> got = entries(y);
    for (int64_t i = first; i < end; ++i)
      for (int c = 0; c < k; ++c) {
        double expected = 0;
        for (int64_t j = 0; j < n; ++j) expected += f[i * n + j] * varied(j, c);
        EXPECT_NEAR(got[(i - first) * k + c], expected, 1e-13 * expected) << i << " " << c;
      }
    ASSERT_EQ(MatGetDiagonal(m, y), 0);
    const std::vector<PetscScalar> diagonal = entries(y);
    for (int64_t i = first; i < end; ++i) {
      // (a difference of sums of order 1: their round-off, a few 1e-16)
      EXPECT_NEAR(diagonal[(i - first) * k], f[i * n + i], 1e-14) << i;
      // (what the two ways' quadratures of the row's other pairs differ by: up to 7e-6 here)
      EXPECT_LT(std::abs(diagonal[(i - first) * k]), 2e-5) << i;
    }
    for (Vec* v : {&x, &y}) ASSERT_EQ(VecDestroy(v), 0);
    ASSERT_EQ(MatDestroy(&block), 0);
  }
  // Row maxima (mirrors among them), the nonzeros counted both ways, and no row read whole.
  Vec v;
  ASSERT_EQ(MatCreateVecs(shell, nullptr, &v), 0);
  ASSERT_EQ(MatGetRowMaxAbs(shell, v, nullptr), 0);
  const std::vector<PetscScalar> largest = entries(v);
  for (int64_t i = first; i < end; ++i) {
    double expected = 0;
    for (int64_t j = 0; j < n; ++j) expected = std::max(expected, std::abs(f[i * n + j]));
    EXPECT_NEAR(largest[i - first], expected, 1e-15 * expected) << i;
  }
  ASSERT_EQ(VecDestroy(&v), 0);
  MatInfo info;
  ASSERT_EQ(MatGetInfo(shell, MAT_GLOBAL_SUM, &info), 0);
  int64_t stored = s.store.entries;
  MPI_Allreduce(MPI_IN_PLACE, &stored, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GE(info.nz_used, 2.0 * static_cast<double>(stored - n));
  PetscInt count;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  EXPECT_NE(MatGetRow(shell, static_cast<PetscInt>(first), &count, nullptr, nullptr), 0);
  PetscPopErrorHandler();
  ASSERT_EQ(MatDestroy(&shell), 0);
}

}  // namespace
}  // namespace radiosity
