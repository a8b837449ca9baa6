// balanceColumns(): Sinkhorn's scaling of S = diag(A) F to the row sums A_i r_i and the column
// sums A_j r_j that reciprocity implies, in place on F's one store. Each sweep is a pass over
// the rank's values for the row factors, one for the columns' partial sums, and a sum of those
// over the ranks (one double per patch).
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/error.h"
#include "solve/repair.h"

namespace radiosity::solve {
namespace {

/// Rows are kept to this share of their sums as sampled. A row off by δ is a surface that loses
/// (or gains) δ J: on a net flux q it weighs δ J / q, 1e-4 of q where J is ten times q, far
/// below the rates' sampling error. The balance itself (the columns) is exact whatever δ.
/// Sinkhorn converges linearly, and slowly where a scene is nearly cut in parts (rooms joined
/// by doors: 1e-4 in 25 sweeps, 1e-5 in 75, then 0.985 a sweep; 1e-12 would take 500 or more).
/// Over-relaxed updates (x ← x^(1−ω) x_plain^ω) diverged there.
constexpr double kTolerance = 1e-5;
constexpr int kMostSweeps = 200;

/// Calls visit(r, column, value&) for every stored value of the rank's rows (a double, or a
/// float in a single-precision store).
template <class Visit>
void forEachValue(formfactor::SplitRows& rows, Visit&& visit) {
  for (auto* block : {&rows.diagonalBlock, &rows.offDiagonalBlock}) {
    const bool diagonal = block == &rows.diagonalBlock;
    for (int64_t r = 0; r < rows.rowCount(); ++r) {
      for (int64_t k = block->rowStart[r]; k < block->rowStart[r + 1]; ++k) {
        const int64_t column =
            diagonal ? rows.firstRow + block->column[k] : rows.offDiagonalColumn(k);
        const auto at = static_cast<size_t>(k);
        if (block->single)
          visit(r, column, block->singleValue[at]);
        else
          visit(r, column, block->value[at]);
      }
    }
  }
}

}  // namespace

BalanceReport balanceColumns(formfactor::SplitRows& rows, const std::vector<double>& localArea,
                             int64_t globalPatchCount, MPI_Comm comm,
                             const std::vector<double>& start) {
  if (rows.columnMap)
    throw Error(exit_code::kFailure, "balanceColumns: F's store is lent to PETSc");
  const int64_t local = rows.rowCount();
  const auto n = static_cast<size_t>(globalPatchCount);
  // The rows' sums as sampled, and every column's target A_j r_j (gathered from the ranks).
  std::vector<double> rowSum(static_cast<size_t>(local), 0);
  forEachValue(rows, [&](int64_t r, int64_t, auto& f) { rowSum[r] += f; });
  std::vector<double> target(n, 0);
  for (int64_t r = 0; r < local; ++r)
    target[static_cast<size_t>(rows.firstRow + r)] = localArea[r] * rowSum[r];
  MPI_Allreduce(MPI_IN_PLACE, target.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);

  std::vector<double> u(static_cast<size_t>(local), 1), v(n, 1), columnSum(n), scaled(local);
  int usable = start.size() == u.size() && std::all_of(start.begin(), start.end(), [](double x) {
                 return std::isfinite(x) && x > 0;
               });
  MPI_Allreduce(MPI_IN_PLACE, &usable, 1, MPI_INT, MPI_MIN, comm);
  if (usable) u = start;
  // Columns: v_j = A_j r_j / Σ_i A_i u_i F_ij.
  auto scaleColumns = [&] {
    std::fill(columnSum.begin(), columnSum.end(), 0.0);
    forEachValue(rows, [&](int64_t r, int64_t j, auto& f) {
      columnSum[static_cast<size_t>(j)] += localArea[r] * u[r] * f;
    });
    MPI_Allreduce(MPI_IN_PLACE, columnSum.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);
    for (size_t j = 0; j < n; ++j)
      if (columnSum[j] > 0) v[j] = target[j] / columnSum[j];
  };
  // Rows: the largest relative distance of one from its sum (returned), and u_i = r_i /
  // Σ_j F_ij v_j.
  auto scaleRows = [&] {
    std::fill(scaled.begin(), scaled.end(), 0.0);
    forEachValue(
        rows, [&](int64_t r, int64_t j, auto& f) { scaled[r] += f * v[static_cast<size_t>(j)]; });
    double defect = 0;
    for (int64_t r = 0; r < local; ++r) {
      if (!(rowSum[r] > 0 && scaled[r] > 0)) continue;
      defect = std::max(defect, std::abs(u[r] * scaled[r] - rowSum[r]) / rowSum[r]);
      u[r] = rowSum[r] / scaled[r];
    }
    MPI_Allreduce(MPI_IN_PLACE, &defect, 1, MPI_DOUBLE, MPI_MAX, comm);
    return defect;
  };
  BalanceReport report;
  {  // the columns as sampled
    std::fill(columnSum.begin(), columnSum.end(), 0.0);
    forEachValue(rows, [&](int64_t r, int64_t j, auto& f) {
      columnSum[static_cast<size_t>(j)] += localArea[r] * f;
    });
    MPI_Allreduce(MPI_IN_PLACE, columnSum.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);
    for (size_t j = 0; j < n; ++j)
      if (target[j] > 0 && columnSum[j] > 0)
        report.columnDefectBefore =
            std::max(report.columnDefectBefore, std::abs(columnSum[j] - target[j]) / target[j]);
  }
  scaleColumns();
  for (int sweep = 1;; ++sweep) {
    const double defect = scaleRows();
    report.iterations = sweep;
    if (defect <= kTolerance || sweep >= kMostSweeps) break;
    scaleColumns();
  }
  // The exact last column step, and where the rows then stand (not rescaled).
  scaleColumns();
  const std::vector<double> keptU = u;
  report.rowDefectAfter = scaleRows();
  u = keptU;
  report.converged = report.rowDefectAfter <= kTolerance;
  report.rowScale = u;
  // F'_ij = u_i F_ij v_j: the columns exact, the rows within the defect.
  forEachValue(rows, [&](int64_t r, int64_t j, auto& f) {
    using Value = std::remove_reference_t<decltype(f)>;
    f = static_cast<Value>(f * u[r] * v[static_cast<size_t>(j)]);
  });
  return report;
}

}  // namespace radiosity::solve
