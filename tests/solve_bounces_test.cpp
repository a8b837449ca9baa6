// The discretisation error carried through the bounces (solve/solution_error.cpp): the δB the
// solve reports for given errors of H is (I − diag(ρ) F)⁻¹ ρ δH of the whole matrix, solved here
// apart by dense elimination, to the bounce solve's tolerance; on the Cornell box and on a stiff
// closed box (ρ = 0.99). Runs on 1 rank (ctest's discovered tests) and on 2 (…_2ranks).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <utility>
#include <vector>

#include "petsc_environment.h"
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

}  // namespace
}  // namespace radiosity
