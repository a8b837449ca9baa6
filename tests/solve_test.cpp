// The PETSc stage: F's one store lent to PETSc, the channels solved together, the shared
// system. Runs on 1 rank (ctest's discovered tests) and on 2 (solve_test_2ranks); every rank
// holds its block of rows as in the program.
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
    ::testing::AddGlobalTestEnvironment(new testing::PetscEnvironment({"solve_test"}));

using namespace testing;  // solve_fixture.h

// F's one store, built piece by piece as the form-factor stage samples and lent to PETSc, makes
// the same matrix bit for bit as the tally assembled at once (MatSetValues), on any number of
// ranks, for both estimators (MIS sums are not whole numbers of hits); and its tally, rebuilt a
// piece at a time, is the sampled one bit for bit, also while PETSc holds the arrays and after.
TEST(OneStore, ThePiecesBuiltMatrixIsTheOneBuiltAtOnceAndGivesTheTallyBack) {
  const Mesh patches = cornell();
  const partition::PatchRange owned = partition::blockOf(patches.triangleCount(), rank(), ranks());
  trace::SceneTracer tracer(patches);
  for (formfactor::Estimator estimator :
       {formfactor::Estimator::kHemisphere, formfactor::Estimator::kEmitterMis}) {
    formfactor::Options options;
    options.raysPerPatch = 96;
    options.seed = 3;
    options.estimator = estimator;
    formfactor::Statistics statistics;
    const formfactor::SampleTally tally =
        formfactor::sampleRows(tracer, patches, owned.begin, owned.end, options, statistics);
    ASSERT_TRUE(formfactor::valuesKeepTheSums(tally));
    formfactor::SplitRows store;  // in pieces of 37 rows, as the stage appends them
    testing::sampleIntoStore(tracer, patches, owned, options, store);
    EXPECT_EQ(store.entries, static_cast<int64_t>(tally.column.size()));
    EXPECT_EQ(formfactor::rowSums(store), formfactor::rowSums(tally));
    const formfactor::SparseRows values = formfactor::toFormFactors(store);
    EXPECT_EQ(values.column, formfactor::toFormFactors(tally).column);
    EXPECT_EQ(values.value, formfactor::toFormFactors(tally).value);

    Mat atOnce, lent;
    ASSERT_EQ(solve::assembleRows(PETSC_COMM_WORLD, tally, nullptr, &atOnce), 0);
    ASSERT_EQ(solve::lendRows(PETSC_COMM_WORLD, store, &lent), 0);
    PetscInt first, end;
    ASSERT_EQ(MatGetOwnershipRange(atOnce, &first, &end), 0);
    for (PetscInt row = first; row < end; ++row) {
      PetscInt n1, n2;
      const PetscInt *c1, *c2;
      const PetscScalar *v1, *v2;
      ASSERT_EQ(MatGetRow(atOnce, row, &n1, &c1, &v1), 0);
      ASSERT_EQ(MatGetRow(lent, row, &n2, &c2, &v2), 0);
      ASSERT_EQ(std::vector<PetscInt>(c1, c1 + n1), std::vector<PetscInt>(c2, c2 + n2));
      ASSERT_EQ(std::vector<PetscScalar>(v1, v1 + n1), std::vector<PetscScalar>(v2, v2 + n2));
      ASSERT_EQ(MatRestoreRow(lent, row, &n2, &c2, &v2), 0);
      ASSERT_EQ(MatRestoreRow(atOnce, row, &n1, &c1, &v1), 0);
    }
    const formfactor::SampleTally whileLent = store.tally(0, store.rowCount());
    ASSERT_EQ(solve::takeRowsBack(&lent, store), 0);
    ASSERT_EQ(MatDestroy(&atOnce), 0);
    for (const formfactor::SampleTally& rebuilt : {whileLent, store.tally(0, store.rowCount())}) {
      EXPECT_EQ(rebuilt.firstRow, tally.firstRow);
      EXPECT_EQ(rebuilt.samples, tally.samples);
      EXPECT_EQ(rebuilt.rowStart, tally.rowStart);
      EXPECT_EQ(rebuilt.column, tally.column);
      EXPECT_EQ(rebuilt.sum, tally.sum);  // (a sum off by one fails: the values are not just close)
    }
    EXPECT_EQ(store.tallyRowStart(), tally.rowStart);
    ASSERT_FALSE(tally.sum.empty());
    // Rows given back as their extension is filled (a rays round): the rest still gives its
    // tally bit for bit; a row given back is refused, not read as zeros.
    const int64_t half = store.rowCount() / 2;
    store.releaseRowsBefore(half);
    const formfactor::SampleTally rest = store.tally(half, store.rowCount());
    const formfactor::SampleTally expected = tally.slice(half, tally.rowCount(), tally.samples);
    EXPECT_EQ(rest.column, expected.column);
    EXPECT_EQ(rest.sum, expected.sum);
    EXPECT_THROW(store.tally(half - 1, store.rowCount()), std::logic_error);
  }
}

// A checkpoint inside the form-factor stage lends F's store as filled so far, not a tally copy of
// it: its rows with their samples, the rows past them with none. Read back (on this decomposition)
// it is the tally of those rows and empty rows, bit for bit, on any number of ranks.
TEST(OneStore, AStoreFilledSoFarIsCheckpointedAsItsTallyAndEmptyRows) {
  const Mesh patches = cornell();
  const partition::PatchRange owned = partition::blockOf(patches.triangleCount(), rank(), ranks());
  trace::SceneTracer tracer(patches);
  formfactor::Options options;
  options.raysPerPatch = 64;
  options.seed = 5;
  options.estimator = formfactor::Estimator::kEmitterMis;
  formfactor::Statistics statistics;
  const int64_t filled = owned.size() / 2;
  formfactor::RowSampling sampling(tracer, patches, options);
  Checkpoint local;
  local.stage = "formfactors";
  local.identity = {{"scene", "builtin:cornell"}};
  local.patchCount = patches.triangleCount();
  local.rows.values.firstRow = owned.begin;
  local.rows.values.endRow = owned.end;
  formfactor::appendRows(local.rows.values, sampling.sample(owned.begin, owned.begin + filled, 0,
                                                            options.raysPerPatch, statistics));
  local.rows.rowSamples.assign(filled, options.raysPerPatch);
  local.rows.rowSamples.resize(owned.size(), 0);
  testing::SharedTempDir dir("solve_test");
  const std::string path = (dir.path() / "partial.h5").string();
  writeCheckpoint(MPI_COMM_WORLD, path, local);
  const Checkpoint back = readCheckpoint(MPI_COMM_WORLD, path, owned.begin, owned.end);
  const formfactor::SampleTally sampled = formfactor::sampleRows(
      tracer, patches, owned.begin, owned.begin + filled, options, statistics);
  ASSERT_GT(sampled.column.size(), 0u);
  EXPECT_EQ(back.rows.rowSamples, local.rows.rowSamples);
  const SampleTally& read = back.rows.tally;
  ASSERT_EQ(read.rowCount(), owned.size());
  EXPECT_EQ(read.slice(0, filled, options.raysPerPatch).column, sampled.column);
  EXPECT_EQ(read.slice(0, filled, options.raysPerPatch).sum, sampled.sum);
  for (int64_t r = filled; r <= owned.size(); ++r)
    ASSERT_EQ(read.rowStart[r], read.rowStart[filled]) << "row " << r << " has entries";
  // A store holding more rows than the checkpoint counts is refused, and nothing is written.
  local.rows.rowSamples.resize(filled - 1);
  EXPECT_THROW(writeCheckpoint(MPI_COMM_WORLD, (dir.path() / "refused.h5").string(), local), Error);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "refused.h5"));
}

// What rows given back return: 64 MiB of a tally's columns and sums leave the resident set at
// once, while the arrays stay where they are.
TEST(OneStore, RowsGivenBackLeaveTheResidentSet) {
  auto resident = [] {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, residentPages = 0;
    statm >> pages >> residentPages;
    return static_cast<double>(residentPages) * static_cast<double>(sysconf(_SC_PAGESIZE));
  };
  SampleTally rows;
  const int64_t count = 1024, perRow = (int64_t{32} << 20) / 8 / count;
  rows.column.assign(count * perRow, 7);
  rows.sum.assign(count * perRow, 9);
  for (int64_t r = 1; r <= count; ++r) rows.rowStart.push_back(r * perRow);
  const void* where = rows.column.data();
  const double before = resident();
  rows.releaseRowsBefore(count - 1);
  EXPECT_LT(resident(), before - 60.0 * (1 << 20));
  EXPECT_EQ(rows.column.data(), where);
  EXPECT_EQ(rows.column.back(), 7);  // the last row is kept
  EXPECT_EQ(rows.sum.back(), 9);
  EXPECT_THROW(rows.slice(0, count, 1), std::logic_error);
}

// Sums a double cannot give back (far more samples than any run casts) are found, so that the
// caller keeps its own copy of the tally instead of trusting the values.
TEST(OneStore, SumsThatValuesCannotKeepAreFound) {
  formfactor::SampleTally tally;
  tally.samples = 1024;
  tally.rowStart = {0, 2};
  tally.column = {1, 2};
  tally.sum = {int64_t{5} << 32, (int64_t{1} << 40) + 3};
  EXPECT_TRUE(formfactor::valuesKeepTheSums(tally));
  tally.sum[1] = (int64_t{1} << 60) + 1;  // beyond the 53 bits of a double
  EXPECT_FALSE(formfactor::valuesKeepTheSums(tally));
}

// The Cornell box's RGB channels solved with the default solver, channels together or one by
// one (PETSc option -solve_channels_together), from the same rows.
struct ChannelsSolved {
  LocalSolution solution;
  solve::Report report;
  std::vector<SolveProgress> saved;  ///< what each save() was given
};
ChannelsSolved solveCornellChannels(bool together, int saveAtCall = 0,
                                    const SolveProgress* resume = nullptr) {
  static const Problem problem = sample(cornell(), 64);
  PetscOptionsSetValue(nullptr, "-solve_channels_together", together ? "true" : "false");
  std::vector<Rgb> reflectance, emission;
  for (int64_t r = 0; r < problem.rows.rowCount(); ++r) {
    reflectance.push_back(problem.patches.reflectance[problem.rows.firstRow + r]);
    emission.push_back(problem.patches.emission[problem.rows.firstRow + r]);
  }
  ChannelsSolved out;
  solve::Options options;
  options.rtol = 1e-9;
  options.resume = resume;
  int calls = 0;
  if (saveAtCall > 0) {
    options.safePoint = [&] {
      return ++calls == saveAtCall ? solve::SafePointAction::kSave
                                   : solve::SafePointAction::kContinue;
    };
    options.save = [&](const SolveProgress& progress, formfactor::SplitRows*) {
      out.saved.push_back(progress);
    };
  }
  out.solution = solve::solveRadiosity(problem.rows, problem.patches.triangleCount(), reflectance,
                                       emission, problem.area, options, out.report);
  PetscOptionsClearValue(nullptr, "-solve_channels_together");
  return out;
}

double largestGap(const LocalSolution& a, const LocalSolution& b) {
  double gap = 0, largest = 0;
  for (size_t i = 0; i < a.radiosity.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      gap = std::max(gap, std::abs(a.radiosity[i][c] - b.radiosity[i][c]));
      largest = std::max(largest, std::abs(b.radiosity[i][c]));
    }
  }
  double all[2] = {gap, largest};
  MPI_Allreduce(MPI_IN_PLACE, all, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return all[0] / all[1];
}

// Three channels in one pass over F per iteration: the same B as one channel at a time, with
// fewer passes over F (a pass multiplies each entry for all three channels).
TEST(ChannelsTogether, TheSameAnswerAsOneByOneWithFewerPassesOverF) {
  const ChannelsSolved together = solveCornellChannels(true);
  const ChannelsSolved apart = solveCornellChannels(false);
  EXPECT_EQ(together.report.channelsSolved, 3);
  EXPECT_LT(largestGap(together.solution, apart.solution), 1e-7);
  EXPECT_LT(together.report.residual, 1e-9);
  EXPECT_LT(together.report.matrixProducts, 0.6 * apart.report.matrixProducts)
      << together.report.matrixProducts << " passes together, " << apart.report.matrixProducts
      << " one by one";
  // The history holds every channel: the block's residual for each, then its own check.
  for (int c = 0; c < 3; ++c) {
    EXPECT_NE(std::find(together.report.history.channel.begin(),
                        together.report.history.channel.end(), c),
              together.report.history.channel.end())
        << "channel " << c;
  }
}

// A library loaded with PETSc turns off glibc's mmap for large blocks and the return of freed
// memory (this test program has it loaded too): returnFreedMemory, which the Runtime calls, gives
// them back, so that F's store and other large arrays leave the process when they are freed.
TEST(Runtime, LargeBlocksAreMappedAndGoBackWhenFreed) {
  solve::returnFreedMemory();
  const size_t before = mallinfo2().hblkhd;
  constexpr size_t kBytes = size_t{64} << 20;
  void* block = std::malloc(kBytes);
  ASSERT_NE(block, nullptr);
  EXPECT_GE(mallinfo2().hblkhd, before + kBytes);
  std::free(block);
  EXPECT_EQ(mallinfo2().hblkhd, before);
}

// A channel with black patches (ρ = 0: B = E) on M itself, black rows inside the system, gives
// the answer, the contraction q and the error bound of the system restricted to R, which is a
// copy of M's R×R block: the copy of F is saved without changing what is solved.
TEST(ChannelSystem, BlackRowsInsideTheSharedMatrixGiveTheAnswerOfTheCopiedBlock) {
  static const Problem problem = sample(cornell(), 64);
  Mat M;
  ASSERT_EQ(solve::assembleRows(PETSC_COMM_WORLD, problem.rows, nullptr, &M), 0);
  Vec rho, weight, emission, area;
  ASSERT_EQ(MatCreateVecs(M, &rho, &emission), 0);
  for (Vec* v : {&weight, &area}) ASSERT_EQ(VecDuplicate(rho, v), 0);
  PetscInt first, end;
  VecGetOwnershipRange(rho, &first, &end);
  for (PetscInt i = first; i < end; ++i) {
    const Rgb& e = problem.patches.emission[i];
    // The lights and every seventh patch black; the lights emit.
    const bool black = e[0] > 0 || i % 7 == 0;
    VecSetValue(rho, i, black ? 0.0 : problem.patches.reflectance[i][0], INSERT_VALUES);
    VecSetValue(emission, i, e[0] > 0 ? e[0] : (i % 7 == 0 ? 0.5 : 0.0), INSERT_VALUES);
    VecSetValue(area, i, problem.area[i - first], INSERT_VALUES);
  }
  for (Vec v : {rho, emission, area}) {
    VecAssemblyBegin(v);
    VecAssemblyEnd(v);
  }
  VecSet(weight, 1.0);
  solve::WorkCount work;
  solve::ChannelSystem shared, copied;
  ASSERT_EQ(solve::buildChannelSystem(M, {rho, weight, emission, area}, true, work, &shared), 0);
  ASSERT_EQ(solve::buildChannelSystem(M, {rho, weight, emission, area}, false, work, &copied), 0);
  EXPECT_EQ(shared.matrix.get(), M) << "no copy of F";
  EXPECT_NE(copied.matrix.get(), M);
  EXPECT_EQ(shared.unknowns, copied.unknowns);
  EXPECT_NEAR(shared.contraction, copied.contraction, 1e-14);
  Vec B[2];
  PetscReal bounds[2];
  int k = 0;
  for (solve::ChannelSystem* system : {&shared, &copied}) {
    solve::HistoryRecorder recorder;
    solve::ChannelOutcome outcome;
    ASSERT_EQ(
        solve::solveWithKsp(*system, solve::Solver::kGmres, 1e-12, recorder, {}, work, outcome), 0);
    ASSERT_TRUE(outcome.converged) << outcome.failure;
    Vec r;
    VecDuplicate(system->rhs, &r);
    ASSERT_EQ(solve::channelResidual(*system, system->solution, r, work), 0);
    ASSERT_EQ(solve::relativeErrorBound(*system, r, system->solution, &bounds[k]), 0);
    VecDestroy(&r);
    VecDuplicate(emission, &B[k]);
    ASSERT_EQ(solve::scatterSolution(*system, emission, B[k]), 0);
    ++k;
  }
  EXPECT_NEAR(bounds[0], bounds[1], 1e-9);
  PetscReal gap, largest;
  VecNorm(B[1], NORM_INFINITY, &largest);
  VecAXPY(B[0], -1.0, B[1]);
  VecNorm(B[0], NORM_INFINITY, &gap);
  EXPECT_LT(gap / largest, 1e-10);
  for (Vec* v : {&B[0], &B[1], &rho, &weight, &emission, &area}) VecDestroy(v);
  MatDestroy(&M);
}

// A safe point inside the block saves every channel of it as in progress with its iterate, and
// the solve resumed from that saving ends where the uninterrupted one did.
TEST(ChannelsTogether, ASaveInsideTheBlockResumesToTheSameAnswer) {
  const ChannelsSolved whole = solveCornellChannels(true);
  const ChannelsSolved interrupted = solveCornellChannels(true, 3);
  ASSERT_EQ(interrupted.saved.size(), 1u);
  const SolveProgress& progress = interrupted.saved.front();
  EXPECT_EQ(progress.channelState, (std::array<int, 3>{1, 1, 1}));
  EXPECT_LT(largestGap(interrupted.solution, whole.solution), 1e-7);
  bool moved = false;  // the saved iterate is the block's, not b
  for (size_t i = 0; i < progress.radiosity.size(); ++i)
    moved = moved || progress.radiosity[i][1] != 0;
  EXPECT_TRUE(moved);
  const ChannelsSolved resumed = solveCornellChannels(true, 0, &progress);
  EXPECT_LT(largestGap(resumed.solution, whole.solution), 1e-7);
}

}  // namespace
}  // namespace radiosity
