// Private to solve/: one channel's linear system, built on the one stored matrix M = diag(w) F
// (w = 1, or the patch areas for the symmetric form) without copying it for the channel.
// Patches with ρ = 0 in the channel (black) are not unknowns: B = E there, and their light
// enters the right-hand side once.
#pragma once

#include <petscksp.h>

#include <functional>
#include <string>
#include <vector>

#include "io/store/result.h"
#include "solve/petsc_handles.h"
#include "solve/solve_types.h"

namespace radiosity::solve {

/// The work a solve does, counted (not timed).
struct WorkCount {
  int64_t matrixProducts = 0;   ///< products with a matrix or a batch of its columns
  int64_t nonzeroProducts = 0;  ///< matrix entries multiplied
};

/// A_c = I − diag(s) M_R on the reflective patches R, s = ρ_c / w: y = b + diag(s) M_R y.
/// Owns its objects (a reference to M where M_R is M itself): they go with it.
/// Where the solver needs no entries of A (sharesM), M itself serves for M_R even with black
/// patches, without a copy of F: the system is then over every patch, s = 0 and b = E on the
/// black rows, whose equations x = E hold from the start iterate on (a Krylov or shooting step
/// never moves them), so R's unknowns see exactly the system above.
struct ChannelSystem {
  OwnedMat matrix;     ///< M_R: M itself when every patch reflects or sharesM, else a copy
  OwnedIs reflective;  ///< global ids of R; null when the vectors are over every patch
  OwnedVec onR;        ///< 1 on R, 0 on the black rows inside the system; null when none are
  OwnedVec scale;      ///< s on R
  OwnedVec area;       ///< patch areas on R
  OwnedVec rhs;        ///< b = E_R + s (M E_black)_R
  OwnedVec solution;   ///< B_R; starts at b
  PetscInt unknowns = 0;
  PetscInt nonzeros = 0;       ///< entries of M_R
  PetscReal emissionNorm = 0;  ///< ‖E‖₂ of the whole channel: residuals are relative to it
  /// Largest row-scaled reflectance q = max_i s_i Σ_j M_ij / (1 − s_i M_ii) on R (Jacobi's
  /// contraction in the ∞-norm) and the diagonal of A on R.
  PetscReal contraction = 0;
  OwnedVec diagonal;
  PetscInt longestRow = 0;  ///< most entries in a row of M_R (for the round-off of a residual)
};

/// The full-length vectors one channel's system is built from.
struct ChannelVectors {
  Vec rho;        ///< ρ_c
  Vec rowWeight;  ///< w
  Vec emission;   ///< E_c
  Vec area;
};

/// Builds the system of one channel on M from its vectors; sharesM: on M itself, black rows
/// inside (for solvers that only multiply by A).
PetscErrorCode buildChannelSystem(Mat M, const ChannelVectors& channel, bool sharesM,
                                  WorkCount& work, ChannelSystem* system);

/// Whether `solver` needs A's entries (a preconditioner built from them), so that a channel
/// with black patches takes a copy of M_R.
bool needsExplicitMatrix(Solver solver);

/// diag(A) and q = max_i s_i Σ_{j≠i} |M_ij| / (1 − s_i M_ii) (Jacobi's contraction in the
/// ∞-norm) into `system`, from the rows of M and system.scale, whose `components` channels are
/// interleaved (1: one channel, M = system.matrix), and M's longest row. With `inR` (one flag
/// per global column), the sum runs over the columns in R only.
PetscErrorCode contractionAndDiagonal(Mat M, PetscInt components, ChannelSystem& system,
                                      const std::vector<char>* inR = nullptr);

/// The solution's start where the system holds black rows: x = b (= E) there.
PetscErrorCode keepBlackRowsAtEmission(const ChannelSystem& system);

/// ‖v‖ over R (v over the system's rows).
PetscErrorCode normOnR(const ChannelSystem& system, Vec v, NormType type, PetscReal* norm);

/// The full-length B: the solution on R, E on the black patches.
PetscErrorCode scatterSolution(const ChannelSystem& system, Vec emission, Vec B);

/// r = b − A x on R (one product with M_R, counted).
PetscErrorCode channelResidual(const ChannelSystem& system, Vec x, Vec r, WorkCount& work);

/// A as a PETSc shell matrix over M_R (MatMult and MatGetDiagonal), counting products.
PetscErrorCode createShellOperator(const ChannelSystem& system, WorkCount& work, Mat* A);
/// The explicit matrix K (nnz entries) behind a shell that counts its products.
PetscErrorCode createCountingOperator(Mat K, PetscInt nonzeros, WorkCount& work, Mat* A);

/// The a-posteriori bound ‖B* − B‖∞ ≤ (‖D⁻¹ r‖∞ + δ) / (1 − q) divided by ‖B‖∞ (∞ when
/// q ≥ 1), δ bounding the round-off of the computed r: γ_n (‖b‖∞ + (1 + q)‖x‖∞) / min D,
/// γ_n = n ε / (1 − n ε), n = longestRow + 2 (Higham's bound for a dot product).
PetscErrorCode relativeErrorBound(const ChannelSystem& system, Vec r, Vec x, PetscReal* bound);

/// What a solver hands back for one channel.
struct ChannelOutcome {
  /// kSave or kStop: a safe point interrupted the solver; system.solution holds its iterate.
  SafePointAction interrupted = SafePointAction::kContinue;
  PetscInt iterations = 0;
  bool converged = false;
  std::string failure;           ///< why not, with the option to change
  double conditionEstimate = 0;  ///< 0: none from the method
  std::string conditionSource;
};

/// The caller's safe point (may be empty: never interrupts).
using SafePoint = std::function<SafePointAction()>;

/// Records (channel, iteration, residual, seconds) into the history.
inline constexpr double kProgressSeconds = 2;

struct HistoryRecorder {
  SolveHistory* history = nullptr;
  int channel = 0;
  double start = 0;            ///< MPI_Wtime() at the start of the solve
  double normalise = 1;        ///< residual norms are divided by this
  int64_t firstIteration = 0;  ///< iterations of this channel before (resumed or interrupted)
  /// Channels solved together: each gets the block's residual (which bounds its own relative
  /// residual) at every iteration; empty: just `channel`.
  std::vector<int> together;
  int channelCount = 3;  ///< Options::channels: 1 names the one channel "grey"
  /// Options::progress (may be null or empty), called at most every kProgressSeconds.
  const std::function<void(const std::string&)>* progress = nullptr;
  mutable double lastProgress = 0;
  void record(int64_t iteration, double residualNorm) const;
};

/// Solves the system with a PETSc KSP (every solver but southwell); leaves B_R in
/// system.solution. `rtol` is relative to system.emissionNorm.
PetscErrorCode solveWithKsp(ChannelSystem& system, Solver solver, double rtol,
                            const HistoryRecorder& history, const SafePoint& safePoint,
                            WorkCount& work, ChannelOutcome& outcome);

/// Progressive refinement (shooting) in parallel batches; see solve.h.
PetscErrorCode solveBySouthwell(ChannelSystem& system, double rtol, const HistoryRecorder& history,
                                const SafePoint& safePoint, WorkCount& work,
                                ChannelOutcome& outcome);

}  // namespace radiosity::solve
