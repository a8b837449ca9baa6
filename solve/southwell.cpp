// Southwell's method (progressive refinement, shooting), in parallel batches. The state is B
// and its residual r = b − A B, the unshot radiosity: shooting patch i adds δ = r_i / A_ii to
// B_i, which zeroes r_i and sends s_j M_ji δ to every r_j. The residual is tracked, not
// recomputed, so ‖r‖ and the bound ‖B* − B‖∞ ≤ ‖D⁻¹ r‖∞ / (1 − q) run along for free; it is
// recomputed exactly (one product) to confirm convergence. Each batch, every patch whose unshot
// power A_i |r_i| is at least θ times the largest shoots: all ranks learn the shooters (ids in
// global order) and update their own rows j through a local column index of M_R. The updates
// come in the shooters' global order, so B does not depend on the number of ranks. Any B is a
// valid start, so a checkpoint needs only B.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "solve/channel_system.h"

namespace radiosity::solve {

namespace {

// This rank's rows of M_R indexed by column: entries of column c are [start[c], start[c+1]).
struct LocalColumns {
  std::vector<PetscInt> start;
  std::vector<PetscInt> row;  ///< local row
  std::vector<PetscScalar> value;
};

PetscErrorCode indexColumns(Mat matrix, LocalColumns& columns) {
  PetscInt first, end, global;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(matrix, &first, &end));
  PetscCall(MatGetSize(matrix, &global, nullptr));
  columns.start.assign(global + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {  // count, then fill
    std::vector<PetscInt> next;
    if (pass == 1) {
      for (PetscInt c = 0; c < global; ++c) columns.start[c + 1] += columns.start[c];
      columns.row.resize(columns.start[global]);
      columns.value.resize(columns.start[global]);
      next.assign(columns.start.begin(), columns.start.end() - 1);
    }
    for (PetscInt row = first; row < end; ++row) {
      PetscInt count;
      const PetscInt* cols;
      const PetscScalar* values;
      PetscCall(MatGetRow(matrix, row, &count, &cols, &values));
      for (PetscInt k = 0; k < count; ++k) {
        if (pass == 0) {
          ++columns.start[cols[k] + 1];
        } else {
          const PetscInt slot = next[cols[k]]++;
          columns.row[slot] = row - first;
          columns.value[slot] = values[k];
        }
      }
      PetscCall(MatRestoreRow(matrix, row, &count, &cols, &values));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode copyOut(Vec v, std::vector<PetscScalar>& to) {
  const PetscScalar* values;
  PetscInt local;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(v, &local));
  PetscCall(VecGetArrayRead(v, &values));
  to.assign(values, values + local);
  PetscCall(VecRestoreArrayRead(v, &values));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode solveBySouthwell(ChannelSystem& system, double rtol, const HistoryRecorder& history,
                                const SafePoint& safePoint, WorkCount& work,
                                ChannelOutcome& outcome) {
  MPI_Comm comm;
  PetscInt first, end, global;
  int ranks;
  LocalColumns columns;
  PetscReal threshold = 0.5;
  PetscInt maxBatches = 100000;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-southwell_threshold", &threshold, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-southwell_max_batches", &maxBatches, nullptr));
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(system.matrix), &comm));
  PetscCallMPI(MPI_Comm_size(comm, &ranks));
  PetscCall(MatGetOwnershipRange(system.matrix, &first, &end));
  PetscCall(MatGetSize(system.matrix, &global, nullptr));
  PetscCall(indexColumns(system.matrix, columns));
  const PetscInt local = end - first;

  Vec residualVector;
  PetscCall(VecDuplicate(system.rhs, &residualVector));
  PetscCall(channelResidual(system, system.solution, residualVector, work));
  std::vector<PetscScalar> r, s, area, diagonal;
  PetscCall(copyOut(residualVector, r));
  PetscCall(copyOut(system.scale, s));
  PetscCall(copyOut(system.area, area));
  PetscCall(copyOut(system.diagonal, diagonal));

  const PetscReal target = rtol * system.emissionNorm;
  PetscScalar* radiosity;
  int64_t localWork = 0;
  std::vector<PetscInt> shooterIds, allIds;
  std::vector<PetscScalar> shooterSteps, allSteps;
  std::vector<int> counts(ranks), offsets(ranks);
  int64_t batch = 0;
  PetscReal residualNorm = 0;
  bool converged = false;
  while (true) {
    PetscReal largestPower = 0, squares = 0, globalPower = 0, globalSquares = 0;
    for (PetscInt j = 0; j < local; ++j) {
      largestPower = std::max(largestPower, std::abs(area[j] * r[j]));
      squares += r[j] * r[j];
    }
    PetscCallMPI(MPIU_Allreduce(&largestPower, &globalPower, 1, MPIU_REAL, MPIU_MAX, comm));
    PetscCallMPI(MPIU_Allreduce(&squares, &globalSquares, 1, MPIU_REAL, MPIU_SUM, comm));
    residualNorm = std::sqrt(globalSquares);
    history.record(history.firstIteration + batch, residualNorm);
    if (residualNorm <= target) {
      // Confirm with the exact residual: the tracked one drifts by round-off.
      PetscCall(channelResidual(system, system.solution, residualVector, work));
      PetscCall(VecNorm(residualVector, NORM_2, &residualNorm));
      if (residualNorm <= target) {
        converged = true;
        break;
      }
      PetscCall(copyOut(residualVector, r));
      continue;
    }
    if (batch >= maxBatches) break;
    if (batch > 0 && safePoint) {
      outcome.interrupted = safePoint();
      if (outcome.interrupted != SafePointAction::kContinue) break;
    }

    shooterIds.clear();
    shooterSteps.clear();
    PetscCall(VecGetArray(system.solution, &radiosity));
    for (PetscInt j = 0; j < local; ++j) {
      if (r[j] != 0 && std::abs(area[j] * r[j]) >= threshold * globalPower) {
        const PetscScalar step = r[j] / diagonal[j];
        shooterIds.push_back(first + j);
        shooterSteps.push_back(step);
        radiosity[j] += step;
        r[j] -= step;  // with the s_i M_ii δ added below, r_i − A_ii δ = 0
      }
    }
    const int mine = static_cast<int>(shooterIds.size());
    PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
    int total = 0;
    for (int k = 0; k < ranks; ++k) {
      offsets[k] = total;
      total += counts[k];
    }
    allIds.resize(total);
    allSteps.resize(total);
    PetscCallMPI(MPI_Allgatherv(shooterIds.data(), mine, MPIU_INT, allIds.data(), counts.data(),
                                offsets.data(), MPIU_INT, comm));
    PetscCallMPI(MPI_Allgatherv(shooterSteps.data(), mine, MPIU_SCALAR, allSteps.data(),
                                counts.data(), offsets.data(), MPIU_SCALAR, comm));
    for (int k = 0; k < total; ++k) {
      const PetscInt c = allIds[k];
      for (PetscInt e = columns.start[c]; e < columns.start[c + 1]; ++e) {
        const PetscInt j = columns.row[e];
        r[j] += s[j] * columns.value[e] * allSteps[k];
      }
      localWork += columns.start[c + 1] - columns.start[c];
    }
    PetscCall(VecRestoreArray(system.solution, &radiosity));
    ++work.matrixProducts;  // a product with a batch of M_R's columns
    ++batch;
  }
  int64_t globalWork = 0;
  PetscCallMPI(MPI_Allreduce(&localWork, &globalWork, 1, MPI_INT64_T, MPI_SUM, comm));
  work.nonzeroProducts += globalWork;
  outcome.iterations = batch;
  outcome.converged = converged;
  if (!converged && outcome.interrupted == SafePointAction::kContinue) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "did not converge within %lld batches (-southwell_max_batches), relative "
                  "residual %.3g; shooting needs about 1/(1 - q) rounds, q = %.6g here: use "
                  "--solver gmres or cg",
                  static_cast<long long>(batch),
                  system.emissionNorm > 0 ? residualNorm / system.emissionNorm : residualNorm,
                  system.contraction);
    outcome.failure = text;
  }
  PetscCall(VecDestroy(&residualVector));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
