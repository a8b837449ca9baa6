// With no --solver, the program picks one from the scene's largest row-scaled reflectance q
// and from whether F is reciprocal (measured in docs/stability.md).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solve/solve.h"

namespace radiosity::solve {

SolverChoice chooseSolver(const std::vector<double>& rowSums, const std::vector<Rgb>& reflectance,
                          bool reciprocal, MPI_Comm comm) {
  double localQ = 0, q = 0;
  for (size_t r = 0; r < rowSums.size(); ++r) {
    const Rgb& rho = reflectance[r];
    localQ = std::max(localQ, rowSums[r] * std::max({rho[0], rho[1], rho[2]}));
  }
  MPI_Allreduce(&localQ, &q, 1, MPI_DOUBLE, MPI_MAX, comm);
  char reason[200];
  if (reciprocal && q < 1) {
    std::snprintf(
        reason, sizeof reason,
        "F is reciprocal and q = %.4g < 1: the symmetric form is positive definite, and CG "
        "keeps 4 vectors where GMRES keeps 32",
        q);
    return {Solver::kCg, reason};
  }
  std::snprintf(reason, sizeof reason,
                "q = %.4g%s; GMRES needs the fewest products with F (docs/stability.md)", q,
                reciprocal ? " >= 1" : " and F is not reciprocal");
  return {Solver::kGmres, reason};
}

}  // namespace radiosity::solve
