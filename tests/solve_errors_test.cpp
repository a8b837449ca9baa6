// The PETSc stage on its error paths: a PETSc error raised in the middle of a solve (here
// -ksp_error_if_not_converged with a KSP that cannot converge) must leave the shared matrix as it
// was (the explicit-form solvers turn it in place into K and back) and free every PETSc object and
// byte that the solve took. PETSc counts its own memory (-malloc_debug), so a leak shows as a
// difference in PetscMallocGetCurrentUsage. Runs on 1 rank (ctest's discovered tests) and on 2
// (solve_errors_test_2ranks), where the error is raised on both ranks together.
#include <gtest/gtest.h>
#include <mpi.h>
#include <petscksp.h>

#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "formfactor/formfactor.h"
#include "partition/partition.h"
#include "petsc_environment.h"
#include "sampled_form_factors.h"
#include "solve/assemble.h"
#include "solve/channel_system.h"
#include "solve/solve.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

// MPI and PETSc for the whole test program, PETSc counting every byte it allocates.
[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(
        new testing::PetscEnvironment({"solve_errors_test", "-malloc_debug"}));

// A closed box (ρ = 0.5, one face emitting) and this rank's rows of its F, as sampled and made
// reciprocal (for cg).
struct Problem {
  Mesh patches;
  formfactor::SparseRows rows, reciprocal;
  std::vector<double> area;
  std::vector<Rgb> reflectance, emission;
};

const Problem& box() {
  static const Problem problem = [] {
    int rank, ranks;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    Problem p;
    Mesh box = testing::closedBox(0.5, 0.0);
    for (size_t t = 0; t < box.triangles.size(); ++t)
      if (box.sourceFace[t] == 0) box.emission[t] = {1, 1, 1};
    p.patches = partition::orderAlongCurve(partition::refine(box, 0.05));
    const partition::PatchRange owned = partition::blockOf(p.patches.triangleCount(), rank, ranks);
    trace::SceneTracer tracer(p.patches);
    formfactor::Statistics statistics;
    formfactor::Options options;
    options.raysPerPatch = 64;
    options.seed = 5;
    p.rows =
        testing::sampledFormFactors(tracer, p.patches, owned.begin, owned.end, options, statistics);
    for (int64_t i = owned.begin; i < owned.end; ++i) {
      p.area.push_back(p.patches.area(i));
      p.reflectance.push_back(p.patches.reflectance[i]);
      p.emission.push_back(p.patches.emission[i]);
    }
    solve::RepairReport report;
    p.reciprocal = solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report);
    return p;
  }();
  return problem;
}

// The bytes PETSc holds on this rank now.
PetscLogDouble petscBytes() {
  PetscLogDouble bytes = 0;
  EXPECT_EQ(PetscMallocGetCurrentUsage(&bytes), 0);
  return bytes;
}

// For the lifetime of the object: every KSP (of options prefix `prefix`) fails with a PETSc
// error after its first iteration, and PETSc returns its errors without printing them. The
// reason is a divergence (a tiny -ksp_divtol), not the iteration limit alone: PETSc does not
// treat DIVERGED_ITS as an error in a KSP it takes for nested, and a KSPSolve that returned an
// error leaves its nesting count one up for the rest of the process.
class FailingKsp {
 public:
  explicit FailingKsp(const std::string& prefix = "") : prefix_(prefix) {
    for (const auto& [name, value] : kOptions)
      PetscOptionsSetValue(nullptr, ("-" + prefix_ + name).c_str(), value);
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  }
  ~FailingKsp() {
    PetscPopErrorHandler();
    for (const auto& [name, value] : kOptions)
      PetscOptionsClearValue(nullptr, ("-" + prefix_ + name).c_str());
  }
  FailingKsp(const FailingKsp&) = delete;
  FailingKsp& operator=(const FailingKsp&) = delete;

 private:
  static constexpr std::pair<const char*, const char*> kOptions[] = {
      {"ksp_error_if_not_converged", "true"}, {"ksp_max_it", "1"}, {"ksp_divtol", "1e-6"}};
  std::string prefix_;
};

LocalSolution solveBox(solve::Solver solver, solve::Report& report) {
  const Problem& p = box();
  solve::Options options;
  options.solver = solver;
  options.rtol = 1e-9;
  return solve::solveRadiosity(p.reciprocal, p.patches.triangleCount(), p.reflectance, p.emission,
                               p.area, options, report);
}

class SolveErrors : public ::testing::TestWithParam<solve::Solver> {};

// The whole solve, failing inside its KSP: the exception the program reports, and every PETSc
// object of the solve freed on the way out (the shared matrix, its vectors, the channel's
// system, the KSP and its operator).
TEST_P(SolveErrors, AFailedSolveFreesEveryPetscObject) {
  solve::Report report;
  solveBox(GetParam(), report);  // first: PETSc's one-time registrations
  ASSERT_TRUE(report.converged);
  const PetscLogDouble before = petscBytes();
  {
    FailingKsp failing;
    try {
      solveBox(GetParam(), report);
      ADD_FAILURE() << "the solve went through";
    } catch (const Error& error) {
      EXPECT_EQ(error.exitCode(), exit_code::kFailure);
      EXPECT_NE(std::string(error.what()).find("PETSc failed in the solve"), std::string::npos)
          << error.what();
    }
  }
  EXPECT_EQ(petscBytes(), before) << "bytes PETSc still holds after the failed solve";
}

// One channel's Krylov solve, failing: gauss-seidel and cg turn the shared matrix in place into
// their explicit form, which must be undone on the error path too, bit for bit.
TEST_P(SolveErrors, AFailedKrylovSolveLeavesTheSharedMatrixAsItWas) {
  const Problem& p = box();
  Mat M, original;
  Vec rho, weight, emission, area;
  ASSERT_EQ(solve::assembleRows(PETSC_COMM_WORLD, p.reciprocal, nullptr, &M), 0);
  ASSERT_EQ(MatDuplicate(M, MAT_COPY_VALUES, &original), 0);
  ASSERT_EQ(MatCreateVecs(M, &rho, &emission), 0);
  for (Vec* v : {&weight, &area}) ASSERT_EQ(VecDuplicate(rho, v), 0);
  VecSet(rho, 0.5);
  VecSet(weight, 1.0);
  VecSet(emission, 1.0);
  VecSet(area, 1.0);
  {
    solve::WorkCount work;
    solve::ChannelSystem system;
    ASSERT_EQ(solve::buildChannelSystem(M, {rho, weight, emission, area},
                                        !solve::needsExplicitMatrix(GetParam()), work, &system),
              0);
    ASSERT_EQ(system.matrix, M) << "every patch reflects: the channel works on M itself";
    solve::HistoryRecorder recorder;
    solve::ChannelOutcome outcome;
    // First a solve that goes through (PETSc's one-time registrations), then one that fails.
    ASSERT_EQ(solve::solveWithKsp(system, GetParam(), 1e-9, recorder, {}, work, outcome), 0);
    EXPECT_TRUE(outcome.converged) << outcome.failure;
    const PetscLogDouble before = petscBytes();
    {
      FailingKsp failing;
      outcome = solve::ChannelOutcome();
      VecCopy(system.rhs, system.solution);  // from b again, far from converged
      EXPECT_NE(solve::solveWithKsp(system, GetParam(), 1e-12, recorder, {}, work, outcome), 0);
    }
    EXPECT_EQ(petscBytes(), before) << "bytes PETSc still holds after the failed Krylov solve";
  }
  MatType type;
  MatGetType(M, &type);
  EXPECT_STREQ(type, MATMPIAIJ);
  PetscBool same = PETSC_FALSE;
  MatEqual(M, original, &same);
  EXPECT_TRUE(same) << "the shared matrix was left in another form";
  for (Vec* v : {&rho, &weight, &emission, &area}) VecDestroy(v);
  MatDestroy(&original);
  MatDestroy(&M);
}

INSTANTIATE_TEST_SUITE_P(Solvers, SolveErrors,
                         ::testing::Values(solve::Solver::kGaussSeidel, solve::Solver::kCg,
                                           solve::Solver::kGmres),
                         [](const auto& info) {
                           return std::string(solve::solverName(info.param)) == "gauss-seidel"
                                      ? std::string("GaussSeidel")
                                      : std::string(solve::solverName(info.param));
                         });

// The form-factor repair, its closure CG failing: the exception, and nothing left behind.
TEST(RepairErrors, AFailedRepairFreesEveryPetscObject) {
  const Problem& p = box();
  solve::RepairReport report;
  solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report);  // one-time registrations
  const PetscLogDouble before = petscBytes();
  {
    FailingKsp failing("repair_");
    EXPECT_THROW(solve::repairFormFactors(p.rows, p.area, {true, 0.0}, report), Error);
  }
  EXPECT_EQ(petscBytes(), before) << "bytes PETSc still holds after the failed repair";
}

}  // namespace
}  // namespace radiosity
