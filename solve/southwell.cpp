// Southwell's progressive refinement (shooting), in parallel batches. The unshot radiosity U
// is the whole state: B = b + diag(s) M (B − U), so the residual is r = diag(s) M U and
// ‖r‖₂ ≤ √n q∞ ‖U‖∞ bounds it for free (q∞ = max_j s_j Σ_i |M_ji|). Each batch, every patch
// whose unshot power A_i U_i is at least θ times the largest shoots: all ranks learn the
// shooters (ids in global order) and add s_j M_ji U_i to their own rows j through a local
// column index of M_R. The order of the additions is the shooters' global order, so the
// answer does not depend on the number of ranks.
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

PetscErrorCode indexColumns(Mat matrix, LocalColumns& columns, std::vector<PetscReal>& rowAbsSum) {
  PetscInt first, end, global;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(matrix, &first, &end));
  PetscCall(MatGetSize(matrix, &global, nullptr));
  columns.start.assign(global + 1, 0);
  rowAbsSum.assign(end - first, 0);
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
          rowAbsSum[row - first] += std::abs(values[k]);
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

}  // namespace

PetscErrorCode solveBySouthwell(ChannelSystem& system, double rtol, const HistoryRecorder& history,
                                WorkCount& work, ChannelOutcome& outcome) {
  MPI_Comm comm;
  PetscInt first, end, global;
  int ranks;
  LocalColumns columns;
  std::vector<PetscReal> rowAbsSum;
  PetscReal threshold = 0.5;
  PetscInt maxBatches = 100000;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-southwell_threshold", &threshold, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-southwell_max_batches", &maxBatches, nullptr));
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(system.matrix), &comm));
  PetscCallMPI(MPI_Comm_size(comm, &ranks));
  PetscCall(MatGetOwnershipRange(system.matrix, &first, &end));
  PetscCall(MatGetSize(system.matrix, &global, nullptr));
  PetscCall(indexColumns(system.matrix, columns, rowAbsSum));
  const PetscInt local = end - first;

  std::vector<PetscScalar> unshot(local), s(local), area(local);
  {
    const PetscScalar* values;
    PetscCall(VecGetArrayRead(system.rhs, &values));
    std::copy(values, values + local, unshot.begin());
    PetscCall(VecRestoreArrayRead(system.rhs, &values));
    PetscCall(VecGetArrayRead(system.scale, &values));
    std::copy(values, values + local, s.begin());
    PetscCall(VecRestoreArrayRead(system.scale, &values));
    PetscCall(VecGetArrayRead(system.area, &values));
    std::copy(values, values + local, area.begin());
    PetscCall(VecRestoreArrayRead(system.area, &values));
  }
  PetscReal localQ = 0, bigQ = 0;
  for (PetscInt j = 0; j < local; ++j) localQ = std::max(localQ, s[j] * rowAbsSum[j]);
  PetscCallMPI(MPIU_Allreduce(&localQ, &bigQ, 1, MPIU_REAL, MPIU_MAX, comm));

  const PetscReal target = rtol * system.emissionNorm;
  Vec r;
  PetscCall(VecDuplicate(system.rhs, &r));
  PetscScalar* radiosity;
  int64_t localWork = 0, workSinceCheck = 0;
  std::vector<PetscInt> shooterIds, allIds;
  std::vector<PetscScalar> shooterValues, allValues;
  std::vector<int> counts(ranks), offsets(ranks);
  PetscInt batch = 0;
  PetscReal residual = 0;
  bool converged = false;
  while (true) {
    PetscReal localMax[2] = {0, 0}, globalMax[2];  // largest unshot power, largest |U|
    for (PetscInt j = 0; j < local; ++j) {
      localMax[0] = std::max(localMax[0], std::abs(area[j] * unshot[j]));
      localMax[1] = std::max(localMax[1], std::abs(unshot[j]));
    }
    PetscCallMPI(MPIU_Allreduce(localMax, globalMax, 2, MPIU_REAL, MPIU_MAX, comm));
    if (std::sqrt(static_cast<PetscReal>(global)) * bigQ * globalMax[1] <= target) {
      converged = true;  // the free bound already guarantees it
      break;
    }
    if (workSinceCheck >= system.nonzeros || batch == 0) {
      // The exact residual costs one product with M_R: at most once per M_R's worth of shots.
      PetscCall(channelResidual(system, system.solution, r, work));
      PetscCall(VecNorm(r, NORM_2, &residual));
      history.record(batch, residual);
      workSinceCheck = 0;
      if (residual <= target) {
        converged = true;
        break;
      }
    }
    if (batch >= maxBatches) break;

    shooterIds.clear();
    shooterValues.clear();
    for (PetscInt j = 0; j < local; ++j) {
      if (unshot[j] != 0 && std::abs(area[j] * unshot[j]) >= threshold * globalMax[0]) {
        shooterIds.push_back(first + j);
        shooterValues.push_back(unshot[j]);
        unshot[j] = 0;
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
    allValues.resize(total);
    PetscCallMPI(MPI_Allgatherv(shooterIds.data(), mine, MPIU_INT, allIds.data(), counts.data(),
                                offsets.data(), MPIU_INT, comm));
    PetscCallMPI(MPI_Allgatherv(shooterValues.data(), mine, MPIU_SCALAR, allValues.data(),
                                counts.data(), offsets.data(), MPIU_SCALAR, comm));

    int64_t batchWork = 0;
    PetscCall(VecGetArray(system.solution, &radiosity));
    for (int k = 0; k < total; ++k) {
      const PetscInt c = allIds[k];
      for (PetscInt e = columns.start[c]; e < columns.start[c + 1]; ++e) {
        const PetscInt j = columns.row[e];
        const PetscScalar arriving = s[j] * columns.value[e] * allValues[k];
        unshot[j] += arriving;
        radiosity[j] += arriving;
      }
      batchWork += columns.start[c + 1] - columns.start[c];
    }
    PetscCall(VecRestoreArray(system.solution, &radiosity));
    localWork += batchWork;
    int64_t globalBatchWork = 0;
    PetscCallMPI(MPI_Allreduce(&batchWork, &globalBatchWork, 1, MPI_INT64_T, MPI_SUM, comm));
    workSinceCheck += globalBatchWork;
    ++work.matrixProducts;  // a product with a batch of M_R's columns
    ++batch;
  }
  int64_t globalWork = 0;
  PetscCallMPI(MPI_Allreduce(&localWork, &globalWork, 1, MPI_INT64_T, MPI_SUM, comm));
  work.nonzeroProducts += globalWork;
  outcome.iterations = batch;
  outcome.converged = converged;
  if (!converged) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "did not converge within %lld batches (-southwell_max_batches), relative "
                  "residual %.3g; shooting needs about 1/(1 - q) rounds, q = %.6g here: use "
                  "--solver gmres or cg",
                  static_cast<long long>(batch),
                  system.emissionNorm > 0 ? residual / system.emissionNorm : residual,
                  system.contraction);
    outcome.failure = text;
  }
  PetscCall(VecDestroy(&r));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
