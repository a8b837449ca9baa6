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
#include "solve/local_rows.h"
#include "solve/petsc_handles.h"

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
    PetscCall(forEachLocalRow(
        matrix, [&](PetscInt row, PetscInt count, const PetscInt* cols, const PetscScalar* values) {
          for (PetscInt k = 0; k < count; ++k) {
            if (pass == 0) {
              ++columns.start[cols[k] + 1];
            } else {
              const PetscInt slot = next[cols[k]]++;
              columns.row[slot] = row - first;
              columns.value[slot] = values[k];
            }
          }
        }));
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

// One channel's shooting: the tracked residual r and what each batch needs at hand (this
// rank's columns of M_R, s, the areas, diag(A)), the batches, and how they ended.
class Shooting {
 public:
  Shooting(ChannelSystem& system, WorkCount& work) : system_(system), work_(work) {}

  PetscErrorCode run(double rtol, const HistoryRecorder& history, const SafePoint& safePoint,
                     ChannelOutcome& outcome) {
    PetscReal threshold = 0.5;
    PetscInt maxBatches = 100000;
    PetscFunctionBeginUser;
    PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-southwell_threshold", &threshold, nullptr));
    PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-southwell_max_batches", &maxBatches, nullptr));
    PetscCall(setUp());
    const PetscReal target = rtol * system_.emissionNorm;
    int64_t batch = 0;
    PetscReal residualNorm = 0;
    bool converged = false;
    while (true) {
      PetscReal globalPower;
      PetscCall(trackedResidual(&globalPower, &residualNorm));
      history.record(history.firstIteration + batch, residualNorm);
      if (residualNorm <= target) {
        // Confirm with the exact residual: the tracked one drifts by round-off.
        PetscCall(channelResidual(system_, system_.solution, residualVector_, work_));
        PetscCall(VecNorm(residualVector_, NORM_2, &residualNorm));
        if (residualNorm <= target) {
          converged = true;
          break;
        }
        PetscCall(copyOut(residualVector_, r_));
        continue;
      }
      if (batch >= maxBatches) break;
      if (batch > 0 && safePoint) {
        outcome.interrupted = safePoint();
        if (outcome.interrupted != SafePointAction::kContinue) break;
      }
      PetscCall(shoot(threshold * globalPower));
      ++work_.matrixProducts;  // a product with a batch of M_R's columns
      ++batch;
    }
    int64_t globalWork = 0;
    PetscCallMPI(MPI_Allreduce(&localWork_, &globalWork, 1, MPI_INT64_T, MPI_SUM, comm_));
    work_.nonzeroProducts += globalWork;
    outcome.iterations = batch;
    outcome.converged = converged;
    if (!converged && outcome.interrupted == SafePointAction::kContinue) {
      char text[300];
      std::snprintf(text, sizeof text,
                    "did not converge within %lld batches (-southwell_max_batches), relative "
                    "residual %.3g; shooting needs about 1/(1 - q) rounds, q = %.6g here: use "
                    "--solver gmres or cg",
                    static_cast<long long>(batch),
                    system_.emissionNorm > 0 ? residualNorm / system_.emissionNorm : residualNorm,
                    system_.contraction);
      outcome.failure = text;
    }
    PetscFunctionReturn(0);
  }

 private:
  PetscErrorCode setUp() {
    PetscInt end;
    PetscFunctionBeginUser;
    PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(system_.matrix.get()), &comm_));
    PetscCallMPI(MPI_Comm_size(comm_, &ranks_));
    PetscCall(MatGetOwnershipRange(system_.matrix, &first_, &end));
    PetscCall(indexColumns(system_.matrix, columns_));
    local_ = end - first_;
    PetscCall(VecDuplicate(system_.rhs, residualVector_.out()));
    PetscCall(channelResidual(system_, system_.solution, residualVector_, work_));
    PetscCall(copyOut(residualVector_, r_));
    PetscCall(copyOut(system_.scale, s_));
    PetscCall(copyOut(system_.area, area_));
    PetscCall(copyOut(system_.diagonal, diagonal_));
    counts_.resize(ranks_);
    offsets_.resize(ranks_);
    PetscFunctionReturn(0);
  }

  // The largest unshot power max_i A_i |r_i| and ‖r‖₂, global.
  PetscErrorCode trackedResidual(PetscReal* globalPower, PetscReal* residualNorm) {
    PetscReal largestPower = 0, squares = 0, globalSquares = 0;
    PetscFunctionBeginUser;
    *globalPower = 0;
    for (PetscInt j = 0; j < local_; ++j) {
      largestPower = std::max(largestPower, std::abs(area_[j] * r_[j]));
      squares += r_[j] * r_[j];
    }
    PetscCallMPI(MPIU_Allreduce(&largestPower, globalPower, 1, MPIU_REAL, MPIU_MAX, comm_));
    PetscCallMPI(MPIU_Allreduce(&squares, &globalSquares, 1, MPIU_REAL, MPIU_SUM, comm_));
    *residualNorm = std::sqrt(globalSquares);
    PetscFunctionReturn(0);
  }

  // One batch: every patch whose unshot power is at least `least` shoots; all ranks learn the
  // shooters in global order and update their own rows.
  PetscErrorCode shoot(PetscReal least) {
    PetscScalar* radiosity;
    PetscFunctionBeginUser;
    shooterIds_.clear();
    shooterSteps_.clear();
    PetscCall(VecGetArray(system_.solution, &radiosity));
    for (PetscInt j = 0; j < local_; ++j) {
      if (r_[j] != 0 && std::abs(area_[j] * r_[j]) >= least) {
        const PetscScalar step = r_[j] / diagonal_[j];
        shooterIds_.push_back(first_ + j);
        shooterSteps_.push_back(step);
        radiosity[j] += step;
        r_[j] -= step;  // with the s_i M_ii δ added below, r_i − A_ii δ = 0
      }
    }
    PetscCall(VecRestoreArray(system_.solution, &radiosity));
    const int mine = static_cast<int>(shooterIds_.size());
    PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts_.data(), 1, MPI_INT, comm_));
    int total = 0;
    for (int k = 0; k < ranks_; ++k) {
      offsets_[k] = total;
      total += counts_[k];
    }
    allIds_.resize(total);
    allSteps_.resize(total);
    PetscCallMPI(MPI_Allgatherv(shooterIds_.data(), mine, MPIU_INT, allIds_.data(), counts_.data(),
                                offsets_.data(), MPIU_INT, comm_));
    PetscCallMPI(MPI_Allgatherv(shooterSteps_.data(), mine, MPIU_SCALAR, allSteps_.data(),
                                counts_.data(), offsets_.data(), MPIU_SCALAR, comm_));
    for (int k = 0; k < total; ++k) {
      const PetscInt c = allIds_[k];
      for (PetscInt e = columns_.start[c]; e < columns_.start[c + 1]; ++e) {
        const PetscInt j = columns_.row[e];
        r_[j] += s_[j] * columns_.value[e] * allSteps_[k];
      }
      localWork_ += columns_.start[c + 1] - columns_.start[c];
    }
    PetscFunctionReturn(0);
  }

  ChannelSystem& system_;
  WorkCount& work_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int ranks_ = 1;
  PetscInt first_ = 0, local_ = 0;
  LocalColumns columns_;
  OwnedVec residualVector_;
  std::vector<PetscScalar> r_, s_, area_, diagonal_;
  int64_t localWork_ = 0;
  std::vector<PetscInt> shooterIds_, allIds_;
  std::vector<PetscScalar> shooterSteps_, allSteps_;
  std::vector<int> counts_, offsets_;
};

}  // namespace

PetscErrorCode solveBySouthwell(ChannelSystem& system, double rtol, const HistoryRecorder& history,
                                const SafePoint& safePoint, WorkCount& work,
                                ChannelOutcome& outcome) {
  Shooting shooting(system, work);
  return shooting.run(rtol, history, safePoint, outcome);
}

}  // namespace radiosity::solve
