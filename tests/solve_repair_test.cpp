// What the PETSc stage does to F before the solve: reciprocity and the conservative repair
// (--reciprocity, --drop-threshold) and a thermal run's balance of its columns. Runs on 1 rank
// and on 2 (solve_repair_test_2ranks); checks gather the whole (small) matrix.
#include <gtest/gtest.h>
#include <malloc.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "io/store/checkpoint.h"
#include "partition/partition.h"
#include "petsc_environment.h"
#include "sampled_form_factors.h"
#include "solve/assemble.h"
#include "solve/channel_system.h"
#include "solve/solve.h"
#include "solve_fixture.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

// MPI and PETSc for the whole test program.
[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new testing::PetscEnvironment({"solve_repair_test"}));

using namespace testing;  // solve_fixture.h

TEST(Reciprocity, SymmetrisesAClosedBoxAndKeepsItsRowsSummingToOne) {
  Problem p = sample(refinedBox(), 64);
  solve::RepairReport report;
  formfactor::SparseRows repaired = solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report);
  EXPECT_EQ(repaired.firstRow, p.rows.firstRow);
  EXPECT_EQ(repaired.rowCount(), p.rows.rowCount());
  formfactor::SparseRows all = gather(repaired);
  ASSERT_EQ(all.rowCount(), p.patches.triangleCount());
  EXPECT_LT(reciprocityError(all, p.patches), 1e-14);
  for (int64_t i = 0; i < all.rowCount(); ++i) EXPECT_NEAR(rowSum(all, i), 1.0, 1e-12) << i;
  expectSortedPositiveRows(all);

  EXPECT_GT(report.reciprocityDefect, 0.05);  // 64 rays: far from reciprocal
  EXPECT_LT(report.defectAfter, 1e-14);
  EXPECT_GT(report.closureBefore, 1e-3);  // averaging alone breaks closure ...
  EXPECT_LT(report.closureAfter, 1e-12);  // ... and the repair restores it
  EXPECT_GT(report.iterations, 0);
  EXPECT_TRUE(report.converged);
  EXPECT_GT(report.change, 0.0);
  EXPECT_LT(report.change, report.reciprocityDefect);
  EXPECT_EQ(report.droppedNonzeroShare, 0.0);
  EXPECT_GE(report.nonzerosAfter, report.nonzerosBefore);  // the union of both patterns
  EXPECT_GT(report.bytesPerPatchBefore, 16.0 * report.nonzerosBefore / all.rowCount());
  EXPECT_EQ(report.negativeKept + report.negativeClipped + report.emptyRows, 0);
}

TEST(Reciprocity, DroppingAFifthOfTheEntriesKeepsReciprocityClosureAndSigns) {
  Problem p = sample(refinedBox(), 256);
  const double threshold = thresholdFor(gather(p.rows), 0.2);
  solve::RepairReport report;
  formfactor::SparseRows repaired =
      solve::repairFormFactors(p.rows, p.area, {true, threshold}, report);
  formfactor::SparseRows all = gather(repaired);
  EXPECT_LT(reciprocityError(all, p.patches), 1e-14);
  for (int64_t i = 0; i < all.rowCount(); ++i) EXPECT_NEAR(rowSum(all, i), 1.0, 1e-12) << i;
  expectSortedPositiveRows(all);
  EXPECT_GT(report.droppedNonzeroShare, 0.15);
  EXPECT_GT(report.droppedWeightShare, 0.0);
  EXPECT_LT(report.droppedWeightShare, report.droppedNonzeroShare);  // the small ones went
  EXPECT_LT(report.nonzerosAfter, report.nonzerosBefore);
  EXPECT_LT(report.bytesPerPatchAfter, report.bytesPerPatchBefore);
  EXPECT_LT(report.closureAfter, 1e-12);
  EXPECT_EQ(report.negativeKept, 0);
  EXPECT_EQ(report.emptyRows, 0);
}

TEST(Reciprocity, DroppingAloneScalesRowsBackToTheirSums) {
  Problem p = sample(refinedBox(), 128);
  formfactor::SparseRows raw = gather(p.rows);
  const double threshold = thresholdFor(raw, 0.2);
  solve::RepairReport report;
  formfactor::SparseRows all =
      gather(solve::repairFormFactors(p.rows, p.area, {false, threshold}, report));
  for (int64_t i = 0; i < all.rowCount(); ++i) {
    EXPECT_NEAR(rowSum(all, i), 1.0, 1e-12);
    for (int64_t k = all.rowStart[i]; k < all.rowStart[i + 1]; ++k) {
      EXPECT_GE(entry(raw, i, all.column[k]), threshold);  // no entry appears
    }
  }
  EXPECT_EQ(report.iterations, 0);
  EXPECT_GT(report.droppedNonzeroShare, 0.15);
  EXPECT_GT(report.defectAfter, 0.0);  // not symmetrised
}

TEST(Reciprocity, AnOpenSceneKeepsItsEstimatedRowSums) {
  Problem p = sample(cornell(), 128);
  solve::RepairReport report;
  formfactor::SparseRows all =
      gather(solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report));
  formfactor::SparseRows raw = gather(p.rows);
  double smallest = 1;
  for (int64_t i = 0; i < all.rowCount(); ++i) {
    EXPECT_NEAR(rowSum(all, i), rowSum(raw, i), 1e-12) << i;
    smallest = std::min(smallest, rowSum(raw, i));
  }
  EXPECT_LT(smallest, 0.9);  // open: rays escape
  EXPECT_LT(reciprocityError(all, p.patches), 1e-14);
  expectSortedPositiveRows(all);
  EXPECT_GT(report.reciprocityDefect, 0.05);
  EXPECT_GT(report.oneSidedShare, 0.0);
  EXPECT_GT(report.maxPairDefect, 0.0);
  EXPECT_LT(report.defectAfter, 1e-14);
  EXPECT_LT(report.closureAfter, 1e-12);
  EXPECT_TRUE(report.converged);
}

// All ranks together give what one rank owning every row gives, to round-off of the CG.
TEST(Reciprocity, TheSameOnAnyNumberOfRanks) {
  const Mesh patches = cornell();
  Problem distributed = sample(patches, 64);
  Problem whole = sample(patches, 64, MPI_COMM_SELF);
  const double threshold = 2.5 / 64;
  solve::RepairReport report, wholeReport;
  formfactor::SparseRows a = gather(
      solve::repairFormFactors(distributed.rows, distributed.area, {true, threshold}, report));
  formfactor::SparseRows b = solve::repairFormFactors(whole.rows, whole.area, {true, threshold},
                                                      wholeReport, MPI_COMM_SELF);
  ASSERT_EQ(a.rowStart, b.rowStart);
  ASSERT_EQ(a.column, b.column);
  for (size_t k = 0; k < a.value.size(); ++k) EXPECT_NEAR(a.value[k], b.value[k], 1e-12);
  EXPECT_EQ(report.nonzerosAfter, wholeReport.nonzerosAfter);
  EXPECT_NEAR(report.reciprocityDefect, wholeReport.reciprocityDefect, 1e-12);  // sum order
  EXPECT_DOUBLE_EQ(report.droppedNonzeroShare, wholeReport.droppedNonzeroShare);
  EXPECT_GT(report.droppedNonzeroShare, 0.1);
}

TEST(Reciprocity, RefusesAreasThatDoNotMatchTheRows) {
  Problem p = sample(refinedBox(), 16);
  p.area.push_back(1.0);
  solve::RepairReport report;
  EXPECT_THROW(solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report), Error);
}

// A thermal run's balance of F (solve::balanceColumns), in place on the store as sampled: the
// columns carry A_j r_j to round-off, the rows keep their sums (to 1e-5), no entry is added, and so
// Σ_i A_i (J_i − Σ_j F'_ij J_j) vanishes for any J in the closed box and the open Cornell box
// alike (there it is what leaves through the opening, Σ_j A_j J_j (1 − r_j)).
TEST(ColumnBalance, ColumnsCarryWhatReciprocitySaysRowsKeepTheirSumsPatternKept) {
  for (const Mesh& patches : {refinedBox(), cornell()}) {
    const partition::PatchRange owned =
        partition::blockOf(patches.triangleCount(), rank(), ranks());
    trace::SceneTracer tracer(patches);
    formfactor::Options options;
    options.raysPerPatch = 64;
    options.seed = 7;
    formfactor::Statistics statistics;
    formfactor::SplitRows store;
    store.firstRow = owned.begin;
    store.endRow = owned.end;
    formfactor::RowSampling sampling(tracer, patches, options);
    formfactor::appendRows(
        store, sampling.sample(owned.begin, owned.end, 0, options.raysPerPatch, statistics));
    std::vector<double> area;
    for (int64_t i = owned.begin; i < owned.end; ++i) area.push_back(patches.area(i));
    const formfactor::SparseRows before = formfactor::toFormFactors(store);
    const std::vector<double> sums = formfactor::rowSums(store);

    formfactor::SplitRows again = store;  // balanced below from where this balance ends (the
                                          // same F within the tolerance)
    const solve::BalanceReport report =
        solve::balanceColumns(store, area, patches.triangleCount(), MPI_COMM_WORLD);
    EXPECT_TRUE(report.converged);
    const solve::BalanceReport resumed = solve::balanceColumns(again, area, patches.triangleCount(),
                                                               MPI_COMM_WORLD, report.rowScale);
    EXPECT_EQ(resumed.iterations, 1);  // its checkpoint's row factors: one sweep
    EXPECT_LE(resumed.rowDefectAfter, report.rowDefectAfter);
    const formfactor::SparseRows fromThere = formfactor::toFormFactors(again);
    EXPECT_GT(report.columnDefectBefore, 1e-3);  // sampled columns are off by their noise
    const formfactor::SparseRows after = formfactor::toFormFactors(store);
    EXPECT_EQ(after.rowStart, before.rowStart);
    EXPECT_EQ(after.column, before.column);
    for (size_t k = 0; k < after.value.size(); ++k)
      ASSERT_NEAR(fromThere.value[k], after.value[k], 2e-5 * after.value[k]);
    const std::vector<double> kept = formfactor::rowSums(store);
    for (size_t r = 0; r < sums.size(); ++r) EXPECT_NEAR(kept[r], sums[r], 1e-5 * sums[r]);

    // Columns, and the balance for a J that varies over the patches.
    const auto n = static_cast<size_t>(patches.triangleCount());
    std::vector<double> column(n, 0), target(n, 0);
    double balance[2] = {0, 0};  // Σ A_i (J_i − H_i) − Σ A_j J_j (1 − r_j), Σ A_i J_i
    auto J = [](int64_t i) { return 1 + 0.5 * std::sin(0.37 * static_cast<double>(i)); };
    for (int64_t r = 0; r < after.rowCount(); ++r) {
      const int64_t i = after.firstRow + r;
      target[static_cast<size_t>(i)] = area[r] * sums[r];
      double h = 0;
      for (int64_t k = after.rowStart[r]; k < after.rowStart[r + 1]; ++k) {
        column[static_cast<size_t>(after.column[k])] += area[r] * after.value[k];
        h += after.value[k] * J(after.column[k]);
      }
      balance[0] += area[r] * (J(i) - h) - area[r] * J(i) * (1 - sums[r]);
      balance[1] += area[r] * J(i);
    }
    MPI_Allreduce(MPI_IN_PLACE, column.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM,
                  MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, target.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM,
                  MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, balance, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    for (size_t j = 0; j < n; ++j) EXPECT_NEAR(column[j], target[j], 1e-13 * target[j]) << j;
    EXPECT_LT(std::abs(balance[0]), 1e-13 * balance[1]);
  }
}

}  // namespace
}  // namespace radiosity
