// The solvers of `--solver` and their names, parsed once on the command line (no PETSc here).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace radiosity::solve {

/// The solvers of `--solver`. Every one stops at the relative residual ‖E − A B‖/‖E‖ ≤ rtol.
///  - jacobi: Richardson preconditioned by the diagonal (the seeds' relaxed Jacobi; PETSc);
///  - gauss-seidel: Richardson with PETSc's SOR, forward sweeps on each rank's rows (ω by
///    -pc_sor_omega; with several ranks it is block Gauss-Seidel);
///  - gmres: right-preconditioned GMRES with point Jacobi (PETSc);
///  - cg: CG on the symmetric form (diag(A/ρ) − S) B = diag(A/ρ) E, S = diag(A) F; needs a
///    reciprocal F (the caller repairs F first, see repairFormFactors);
///  - chebyshev: Chebyshev iteration with the eigenvalue bounds 1 ∓ q derived from the largest
///    row-scaled reflectance q (PETSc; -ksp_chebyshev_eigenvalues overrides); the eigenvalues
///    are real only for a reciprocal F, so it needs one like cg;
///  - southwell: progressive refinement in parallel batches: every patch whose unshot power
///    A_i ΔB_i is at least a share θ of the largest shoots it (-southwell_threshold θ, 0.5).
enum class Solver { kJacobi, kGaussSeidel, kGmres, kCg, kChebyshev, kSouthwell };

/// The solver's name on the command line, in the logs and in the result file.
inline const char* solverName(Solver solver) {
  switch (solver) {
    case Solver::kJacobi:
      return "jacobi";
    case Solver::kGaussSeidel:
      return "gauss-seidel";
    case Solver::kGmres:
      return "gmres";
    case Solver::kCg:
      return "cg";
    case Solver::kChebyshev:
      return "chebyshev";
    case Solver::kSouthwell:
      return "southwell";
  }
  return "unknown";
}

/// Every solver's name, in the order of the enum (the values `--solver` accepts).
inline const std::vector<std::string>& solverNames() {
  static const std::vector<std::string> names{
      solverName(Solver::kJacobi),    solverName(Solver::kGaussSeidel),
      solverName(Solver::kGmres),     solverName(Solver::kCg),
      solverName(Solver::kChebyshev), solverName(Solver::kSouthwell)};
  return names;
}

/// The solver of that name; throws std::invalid_argument for any other.
inline Solver solverNamed(const std::string& name) {
  for (Solver solver : {Solver::kJacobi, Solver::kGaussSeidel, Solver::kGmres, Solver::kCg,
                        Solver::kChebyshev, Solver::kSouthwell}) {
    if (name == solverName(solver)) return solver;
  }
  throw std::invalid_argument("unknown solver '" + name + "'");
}

/// cg iterates on the symmetric form and chebyshev relies on real eigenvalues: both need
/// A_i F_ij = A_j F_ji, so the caller repairs F first (repairFormFactors with reciprocity).
inline bool needsReciprocity(Solver solver) {
  return solver == Solver::kCg || solver == Solver::kChebyshev;
}

}  // namespace radiosity::solve
