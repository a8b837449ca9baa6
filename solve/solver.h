// The solvers of `--solver` and their names, parsed once on the command line (no PETSc here).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "core/enum_names.h"

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

/// The solvers' names on the command line, in the logs and in the result file, in the order of
/// the enum, with what --help says of each.
inline constexpr NamedValue<Solver> kSolverNames[] = {
    {Solver::kJacobi, "jacobi"},
    {Solver::kGaussSeidel, "gauss-seidel"},
    {Solver::kGmres, "gmres"},
    {Solver::kCg, "cg"},
    {Solver::kChebyshev, "chebyshev", "these two enforce reciprocity"},
    {Solver::kSouthwell, "southwell"},
};

/// The solver's name.
inline const char* solverName(Solver solver) { return nameIn(kSolverNames, solver); }

/// Every solver's name, in the order of the enum (the values `--solver` accepts).
inline const std::vector<std::string>& solverNames() {
  static const std::vector<std::string> names = namesIn(kSolverNames);
  return names;
}

/// The solver of that name; throws std::invalid_argument for any other.
inline Solver solverNamed(const std::string& name) {
  if (const auto solver = valueNamed(kSolverNames, name)) return *solver;
  throw std::invalid_argument("unknown solver '" + name + "'");
}

/// cg iterates on the symmetric form and chebyshev relies on real eigenvalues: both need
/// A_i F_ij = A_j F_ji, so the caller repairs F first (repairFormFactors with reciprocity).
inline bool needsReciprocity(Solver solver) {
  return solver == Solver::kCg || solver == Solver::kChebyshev;
}

}  // namespace radiosity::solve
