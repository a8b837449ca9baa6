// The discretisation error carried through the bounces (solve/solution_error.cpp): the δB the
// solve reports for given errors of H is (I − diag(ρ) F)⁻¹ ρ δH of the whole matrix, solved here
// apart by dense elimination, to the bounce solve's tolerance; on the Cornell box and on a stiff
// closed box (ρ = 0.99); and BiCGStab's fall back to GMRES where it breaks down. Runs on 1 rank
// (ctest's discovered tests) and on 2 (…_2ranks).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <utility>
#include <vector>

#include "petsc_environment.h"
#include "solve/petsc_handles.h"
#include "solve/solution_error.h"
#include "solve/solve.h"
#include "solve_fixture.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

[[maybe_unused]] const ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new testing::PetscEnvironment({"solve_bounces_test"}));

using namespace testing;  // solve_fixture.h

// The error of H the test gives row i (global): signed, of varied size; the same in every channel
// (the solve takes channels of equal ρ and E, as in the box, to have equal errors).
double givenErrorH(int64_t i, int /*channel*/) {
  return 0.1 * std::sin(0.37 * static_cast<double>(i));
}

// x of A x = b by Gaussian elimination with partial pivoting (A dense, row-major, n × n).
std::vector<double> solveDense(std::vector<double> a, std::vector<double> b) {
  const size_t n = b.size();
  for (size_t k = 0; k < n; ++k) {
    size_t pivot = k;
    for (size_t i = k + 1; i < n; ++i)
      if (std::abs(a[i * n + k]) > std::abs(a[pivot * n + k])) pivot = i;
    for (size_t j = 0; j < n; ++j) std::swap(a[k * n + j], a[pivot * n + j]);
    std::swap(b[k], b[pivot]);
    for (size_t i = k + 1; i < n; ++i) {
      const double factor = a[i * n + k] / a[k * n + k];
      for (size_t j = k; j < n; ++j) a[i * n + j] -= factor * a[k * n + j];
      b[i] -= factor * b[k];
    }
  }
  std::vector<double> x(n);
  for (size_t k = n; k-- > 0;) {
    double sum = b[k];
    for (size_t j = k + 1; j < n; ++j) sum -= a[k * n + j] * x[j];
    x[k] = sum / a[k * n + k];
  }
  return x;
}

// RMS of (reported − exact) over RMS of exact, this rank's rows of every channel, over all ranks;
// the exact δB and δH = δH_row + F δB from the whole matrix.
struct Gaps {
  double radiosity = 0, irradiance = 0;
};

Gaps bounceGaps(const Problem& problem) {
  const int64_t n = problem.patches.triangleCount();
  const int64_t first = problem.rows.firstRow, count = problem.rows.rowCount();
  std::vector<Rgb> reflectance, emission;
  for (int64_t r = 0; r < count; ++r) {
    reflectance.push_back(problem.patches.reflectance[first + r]);
    emission.push_back(problem.patches.emission[first + r]);
  }
  solve::Options options;
  options.samplesPerRow = 64;
  options.discretisation = [&](const std::vector<Rgb>& irradiance, std::vector<Rgb>& error,
                               std::vector<Rgb>& variance) {
    error.assign(irradiance.size(), Rgb{0, 0, 0});
    variance.assign(irradiance.size(), Rgb{0, 0, 0});  // (no noise to take out)
    for (int64_t r = 0; r < count; ++r)
      for (int c = 0; c < 3; ++c) error[r][c] = givenErrorH(first + r, c);
  };
  solve::Report report;
  const LocalSolution solution =
      solve::solveRadiosity(problem.rows, n, reflectance, emission, problem.area, options, report);
  EXPECT_EQ(solution.radiosityDiscretisation.size(), static_cast<size_t>(count));
  EXPECT_EQ(solution.irradianceDiscretisation.size(), static_cast<size_t>(count));

  const formfactor::SparseRows all = gather(problem.rows);
  double sums[4] = {0, 0, 0, 0};  // Σ gap² and Σ exact², of B and of H
  for (int c = 0; c < 3; ++c) {
    std::vector<double> a(n * n, 0.0), b(n);
    for (int64_t i = 0; i < n; ++i) {
      const double rho = problem.patches.reflectance[i][c];
      a[i * n + i] = 1;
      for (int64_t k = all.rowStart[i]; k < all.rowStart[i + 1]; ++k)
        a[i * n + all.column[k]] -= rho * all.value[k];
      b[i] = rho * givenErrorH(i, c);
    }
    const std::vector<double> deltaB = solveDense(std::move(a), std::move(b));
    for (int64_t r = 0; r < count; ++r) {
      const int64_t i = first + r;
      double deltaH = givenErrorH(i, c);
      for (int64_t k = all.rowStart[i]; k < all.rowStart[i + 1]; ++k)
        deltaH += all.value[k] * deltaB[all.column[k]];
      sums[0] += std::pow(solution.radiosityDiscretisation[r][c] - deltaB[i], 2);
      sums[1] += deltaB[i] * deltaB[i];
      sums[2] += std::pow(solution.irradianceDiscretisation[r][c] - deltaH, 2);
      sums[3] += deltaH * deltaH;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return {std::sqrt(sums[0] / sums[1]), std::sqrt(sums[2] / sums[3])};
}

// The bounce solve stops at a relative residual of 1e-4; (I − ρ F)⁻¹ magnifies that at most
// 1 / (1 − ρ) = 100 times in the stiff box.
constexpr double kBounceTolerance = 1e-2;

TEST(DiscretisationBounces, AreTheWholeMatrixsSolveOnTheCornellBox) {
  const Problem problem = sample(cornell(), 64);
  const Gaps gaps = bounceGaps(problem);
  EXPECT_LT(gaps.radiosity, kBounceTolerance);
  EXPECT_LT(gaps.irradiance, kBounceTolerance);
}

// ρ = 0.99 in a closed box: ρ F nearly not a contraction, some 100 bounces carry δB.
TEST(DiscretisationBounces, AreTheWholeMatrixsSolveInAStiffClosedBox) {
  const Problem problem =
      sample(partition::orderAlongCurve(partition::refine(closedBox(0.99, 1.0), 0.05)), 64);
  const Gaps gaps = bounceGaps(problem);
  EXPECT_LT(gaps.radiosity, kBounceTolerance);
  EXPECT_LT(gaps.irradiance, kBounceTolerance);
}

// y = (c I + R) x, R turning each pair of unknowns (x_2k, x_2k+1) by a right angle: R is
// skew-symmetric, (r, R r) = 0 for every r, so at c = 0 BiCGStab breaks down on its first step.
// R² = −I gives the answer: (c I + R)⁻¹ = (c I − R) / (c² + 1).
PetscErrorCode turn(Mat A, Vec x, Vec y) {
  const double* c = nullptr;
  const PetscScalar* in;
  PetscScalar* out;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &c));
  PetscCall(VecGetLocalSize(x, &n));
  PetscCall(VecGetArrayRead(x, &in));
  PetscCall(VecGetArray(y, &out));
  for (PetscInt k = 0; k + 1 < n; k += 2) {
    out[k] = *c * in[k] + in[k + 1];
    out[k + 1] = *c * in[k + 1] - in[k];
  }
  PetscCall(VecRestoreArray(y, &out));
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscFunctionReturn(0);
}

struct TurnSolved {
  bool fellBack = false;
  double error = 0;  ///< largest |x − x*| over the unknowns
};

TurnSolved solveTurn(double c) {
  constexpr PetscInt kLocal = 40;
  TurnSolved solved;
  solve::OwnedMat A;
  solve::OwnedKsp ksp;
  solve::OwnedVec b, x;
  PC pc;
  PetscCallAbort(PETSC_COMM_WORLD, MatCreateShell(PETSC_COMM_WORLD, kLocal, kLocal, PETSC_DETERMINE,
                                                  PETSC_DETERMINE, &c, A.out()));
  PetscCallAbort(PETSC_COMM_WORLD,
                 MatShellSetOperation(A, MATOP_MULT, reinterpret_cast<void (*)(void)>(turn)));
  PetscCallAbort(PETSC_COMM_WORLD, MatCreateVecs(A, x.out(), b.out()));
  PetscInt first;
  PetscCallAbort(PETSC_COMM_WORLD, VecGetOwnershipRange(b, &first, nullptr));
  for (PetscInt k = 0; k < kLocal; ++k)
    PetscCallAbort(PETSC_COMM_WORLD,
                   VecSetValue(b, first + k, std::sin(0.7 * (first + k) + 0.3), INSERT_VALUES));
  PetscCallAbort(PETSC_COMM_WORLD, VecAssemblyBegin(b));
  PetscCallAbort(PETSC_COMM_WORLD, VecAssemblyEnd(b));
  PetscCallAbort(PETSC_COMM_WORLD, KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  PetscCallAbort(PETSC_COMM_WORLD, KSPSetOperators(ksp, A, A));
  PetscCallAbort(PETSC_COMM_WORLD, KSPGetPC(ksp, &pc));
  PetscCallAbort(PETSC_COMM_WORLD, PCSetType(pc, PCNONE));
  PetscCallAbort(PETSC_COMM_WORLD,
                 solve::solveBiCGStabElseGmres(ksp, b, x, 1e-10, &solved.fellBack));
  const PetscScalar *in, *out;
  PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(b, &in));
  PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(x, &out));
  for (PetscInt k = 0; k < kLocal; k += 2) {
    const double x0 = (c * in[k] - in[k + 1]) / (c * c + 1),
                 x1 = (c * in[k + 1] + in[k]) / (c * c + 1);
    solved.error = std::max({solved.error, std::abs(out[k] - x0), std::abs(out[k + 1] - x1)});
  }
  PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(x, &out));
  PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(b, &in));
  MPI_Allreduce(MPI_IN_PLACE, &solved.error, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return solved;
}

TEST(DiscretisationBounces, GmresSolvesWhereBiCGStabBreaksDown) {
  const TurnSolved broke = solveTurn(0);
  EXPECT_TRUE(broke.fellBack);
  EXPECT_LT(broke.error, 1e-8);
  const TurnSolved held = solveTurn(1);  // (r, (I + R) r) = |r|²: no breakdown
  EXPECT_FALSE(held.fellBack);
  EXPECT_LT(held.error, 1e-8);
}

}  // namespace
}  // namespace radiosity
