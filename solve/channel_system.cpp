// One channel's system built on M (channel_system.h): the reflective patches picked out, the
// black ones' light moved into b, the contraction and diagonal for the error bound, and the
// residual, bound and recorded history of an iterate. The shell operator over it is
// channel_operator.cpp's.
#include "solve/channel_system.h"

#include "core/channels.h"
#include "solve/local_rows.h"
#include "solve/petsc_handles.h"
#include "solve/single_precision_matrix.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace radiosity::solve {

namespace {

// Zeroes the entries of `v` at the reflective patches (ρ > 0), leaving the black ones.
PetscErrorCode keepBlackEntries(Vec v, Vec rho) {
  PetscScalar* values;
  const PetscScalar* r;
  PetscInt local;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(v, &local));
  PetscCall(VecGetArray(v, &values));
  PetscCall(VecGetArrayRead(rho, &r));
  for (PetscInt i = 0; i < local; ++i)
    if (r[i] > 0) values[i] = 0;
  PetscCall(VecRestoreArrayRead(rho, &r));
  PetscCall(VecRestoreArray(v, &values));
  PetscFunctionReturn(0);
}

// A full-length vector restricted to R (a copy either way).
PetscErrorCode restrictToReflective(const ChannelSystem& system, Vec full, OwnedVec& reduced) {
  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(system.matrix, reduced.out(), nullptr));
  if (system.reflective) {
    PetscCall(VecISCopy(full, system.reflective, SCATTER_REVERSE, reduced));
  } else {
    PetscCall(VecCopy(full, reduced));
  }
  PetscFunctionReturn(0);
}

// Black patches: B = E; the light they emit reaches R once, through the right-hand side:
// rhs += s ⊙ (M E_black).
PetscErrorCode addBlackPatchesLight(Mat M, Vec rho, Vec emission, Vec scale, Vec rhs,
                                    WorkCount& work) {
  OwnedVec black;
  PetscReal blackEmission;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(emission, black.out()));
  PetscCall(VecCopy(emission, black));
  PetscCall(keepBlackEntries(black, rho));
  PetscCall(VecNorm(black, NORM_INFINITY, &blackEmission));
  if (blackEmission > 0) {
    OwnedVec arriving;
    MatInfo info;
    PetscCall(VecDuplicate(emission, arriving.out()));
    PetscCall(MatMult(M, black, arriving));
    PetscCall(MatGetInfo(M, MAT_GLOBAL_SUM, &info));
    ++work.matrixProducts;
    work.nonzeroProducts += static_cast<int64_t>(info.nz_used);
    PetscCall(VecPointwiseMult(arriving, scale, arriving));
    PetscCall(VecAXPY(rhs, 1.0, arriving));
  }
  PetscFunctionReturn(0);
}

// One flag per global patch, 1 where ρ > 0, on every rank (for the columns of M's rows).
PetscErrorCode gatherReflective(MPI_Comm comm, const std::vector<PetscInt>& reflective,
                                PetscInt first, PetscInt end, std::vector<char>* inR) {
  int ranks;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &ranks));
  std::vector<char> mine(static_cast<size_t>(end - first), 0);
  for (PetscInt i : reflective) mine[static_cast<size_t>(i - first)] = 1;
  std::vector<int> counts(static_cast<size_t>(ranks)), offsets(static_cast<size_t>(ranks), 0);
  const int count = static_cast<int>(mine.size());
  PetscCallMPI(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  inR->assign(static_cast<size_t>(offsets.back() + counts.back()), 0);
  PetscCallMPI(MPI_Allgatherv(mine.data(), count, MPI_CHAR, inR->data(), counts.data(),
                              offsets.data(), MPI_CHAR, comm));
  PetscFunctionReturn(0);
}

// The system over every patch on M itself, black rows inside: s = 0 and b = E there.
PetscErrorCode shareWithBlackRows(Mat M, Vec scaleAll, Vec emission, Vec area,
                                  const std::vector<PetscInt>& reflective, ChannelSystem* system) {
  MPI_Comm comm;
  PetscInt first, end;
  std::vector<char> inR;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(M), &comm));
  PetscCall(shareInto(M, system->matrix));
  PetscCall(VecDuplicate(scaleAll, system->scale.out()));
  PetscCall(VecCopy(scaleAll, system->scale));
  PetscCall(VecDuplicate(emission, system->rhs.out()));
  PetscCall(VecCopy(emission, system->rhs));
  PetscCall(VecDuplicate(area, system->area.out()));
  PetscCall(VecCopy(area, system->area));
  PetscCall(VecDuplicate(scaleAll, system->onR.out()));
  PetscCall(VecGetOwnershipRange(scaleAll, &first, &end));
  PetscCall(VecSet(system->onR, 0));
  for (PetscInt i : reflective) PetscCall(VecSetValue(system->onR, i, 1, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(system->onR));
  PetscCall(VecAssemblyEnd(system->onR));
  PetscCall(VecDuplicate(system->rhs, system->solution.out()));
  PetscCall(VecCopy(system->rhs, system->solution));
  MatInfo info;
  PetscCall(MatGetInfo(M, MAT_GLOBAL_SUM, &info));
  system->nonzeros = static_cast<PetscInt>(info.nz_used);
  PetscCall(gatherReflective(comm, reflective, first, end, &inR));
  PetscCall(contractionAndDiagonal(M, 1, *system, &inR));
  PetscFunctionReturn(0);
}

}  // namespace

bool needsExplicitMatrix(Solver solver) {
  return solver == Solver::kGaussSeidel || solver == Solver::kCg;
}

PetscErrorCode keepBlackRowsAtEmission(const ChannelSystem& system) {
  PetscFunctionBeginUser;
  if (!system.onR) PetscFunctionReturn(0);
  PetscScalar* x;
  const PetscScalar *on, *b;
  PetscInt local;
  PetscCall(VecGetLocalSize(system.solution, &local));
  PetscCall(VecGetArray(system.solution, &x));
  PetscCall(VecGetArrayRead(system.onR, &on));
  PetscCall(VecGetArrayRead(system.rhs, &b));
  for (PetscInt i = 0; i < local; ++i)
    if (on[i] == 0) x[i] = b[i];
  PetscCall(VecRestoreArrayRead(system.rhs, &b));
  PetscCall(VecRestoreArrayRead(system.onR, &on));
  PetscCall(VecRestoreArray(system.solution, &x));
  PetscFunctionReturn(0);
}

PetscErrorCode normOnR(const ChannelSystem& system, Vec v, NormType type, PetscReal* norm) {
  PetscFunctionBeginUser;
  if (!system.onR) {
    PetscCall(VecNorm(v, type, norm));
    PetscFunctionReturn(0);
  }
  OwnedVec masked;
  PetscCall(VecDuplicate(v, masked.out()));
  PetscCall(VecPointwiseMult(masked, system.onR, v));
  PetscCall(VecNorm(masked, type, norm));
  PetscFunctionReturn(0);
}

PetscErrorCode buildChannelSystem(Mat M, const ChannelVectors& channel, bool sharesM,
                                  WorkCount& work, ChannelSystem* system) {
  Vec rho = channel.rho, rowWeight = channel.rowWeight, emission = channel.emission,
      area = channel.area;
  MPI_Comm comm;
  PetscInt first, end, patches;
  OwnedVec scaleAll, rhsAll;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(M), &comm));
  PetscCall(MatGetSize(M, &patches, nullptr));
  PetscCall(VecGetOwnershipRange(rho, &first, &end));
  std::vector<PetscInt> reflective;
  {
    const PetscScalar* r;
    PetscCall(VecGetArrayRead(rho, &r));
    for (PetscInt i = first; i < end; ++i)
      if (r[i - first] > 0) reflective.push_back(i);
    PetscCall(VecRestoreArrayRead(rho, &r));
  }
  const PetscInt localUnknowns = static_cast<PetscInt>(reflective.size());
  PetscCallMPI(MPIU_Allreduce(&localUnknowns, &system->unknowns, 1, MPIU_INT, MPI_SUM, comm));
  PetscCall(VecNorm(emission, NORM_2, &system->emissionNorm));

  PetscCall(VecDuplicate(rho, scaleAll.out()));
  PetscCall(VecPointwiseDivide(scaleAll, rho, rowWeight));  // s = ρ / w
  PetscCall(VecDuplicate(emission, rhsAll.out()));
  PetscCall(VecCopy(emission, rhsAll));
  if (system->unknowns < patches && sharesM) {
    PetscCall(shareWithBlackRows(M, scaleAll, emission, area, reflective, system));
    PetscFunctionReturn(0);
  }
  if (system->unknowns < patches) {
    PetscCall(addBlackPatchesLight(M, rho, emission, scaleAll, rhsAll, work));
    PetscCall(ISCreateGeneral(comm, localUnknowns, reflective.data(), PETSC_COPY_VALUES,
                              system->reflective.out()));
    PetscCall(MatCreateSubMatrix(M, system->reflective, system->reflective, MAT_INITIAL_MATRIX,
                                 system->matrix.out()));
  } else {
    PetscCall(shareInto(M, system->matrix));
  }
  PetscCall(restrictToReflective(*system, rhsAll, system->rhs));
  PetscCall(restrictToReflective(*system, scaleAll, system->scale));
  PetscCall(restrictToReflective(*system, area, system->area));
  PetscCall(VecDuplicate(system->rhs, system->solution.out()));
  PetscCall(VecCopy(system->rhs, system->solution));  // zeroth and first bounce: a cheap guess
  scaleAll.reset();
  rhsAll.reset();
  MatInfo info;
  PetscCall(MatGetInfo(system->matrix, MAT_GLOBAL_SUM, &info));
  system->nonzeros = static_cast<PetscInt>(info.nz_used);
  PetscCall(contractionAndDiagonal(system->matrix, 1, *system));
  PetscFunctionReturn(0);
}

namespace {

// contractionAndDiagonal for F's rows stored once a pair, which cannot be read whole: each row's
// sum over R from one product with R's mask (F's entries off the diagonal are ≥ 0), its diagonal
// from MatGetDiagonal, and for a row's length F's columns (at most that).
PetscErrorCode pairsContractionAndDiagonal(Mat M, PetscInt components, ChannelSystem& system,
                                           const std::vector<char>* inR) {
  PetscInt first, end, columns;
  OwnedVec mask, sumOverR, diagonal;
  const PetscScalar *s, *m, *sum, *on;
  PetscScalar* d;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(M, &first, &end));
  PetscCall(MatGetSize(M, nullptr, &columns));
  PetscCall(MatCreateVecs(M, mask.out(), sumOverR.out()));
  PetscCall(VecDuplicate(sumOverR, diagonal.out()));
  PetscCall(VecSet(mask, 1));
  if (inR) {
    PetscScalar* values;
    PetscCall(VecGetArray(mask, &values));
    for (PetscInt i = first; i < end; ++i) values[i - first] = (*inR)[static_cast<size_t>(i)];
    PetscCall(VecRestoreArray(mask, &values));
  }
  PetscCall(MatMult(M, mask, sumOverR));
  PetscCall(MatGetDiagonal(M, diagonal));
  PetscCall(VecDuplicate(system.rhs, system.diagonal.out()));
  PetscCall(VecGetArrayRead(system.scale, &s));
  PetscCall(VecGetArrayRead(mask, &m));
  PetscCall(VecGetArrayRead(sumOverR, &sum));
  PetscCall(VecGetArrayRead(diagonal, &on));
  PetscCall(VecGetArray(system.diagonal, &d));
  PetscReal q = 0;
  for (PetscInt r = 0; r < end - first; ++r) {
    const PetscReal offDiagonal = std::max(0.0, sum[r] - on[r] * m[r]);
    for (PetscInt j = 0; j < components; ++j) {
      const PetscInt at = r * components + j;
      d[at] = 1 - s[at] * on[r];
      q = std::max(q, s[at] * offDiagonal / d[at]);
    }
  }
  PetscCall(VecRestoreArray(system.diagonal, &d));
  PetscCall(VecRestoreArrayRead(diagonal, &on));
  PetscCall(VecRestoreArrayRead(sumOverR, &sum));
  PetscCall(VecRestoreArrayRead(mask, &m));
  PetscCall(VecRestoreArrayRead(system.scale, &s));
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(M));
  PetscCallMPI(MPIU_Allreduce(&q, &system.contraction, 1, MPIU_REAL, MPIU_MAX, comm));
  system.longestRow = columns;
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode contractionAndDiagonal(Mat M, PetscInt components, ChannelSystem& system,
                                      const std::vector<char>* inR) {
  PetscInt first, end;
  const PetscScalar* s;
  PetscScalar* d;
  PetscFunctionBeginUser;
  if (holdsPairsOnce(M)) {
    PetscCall(pairsContractionAndDiagonal(M, components, system, inR));
    PetscFunctionReturn(0);
  }
  PetscCall(VecDuplicate(system.rhs, system.diagonal.out()));
  PetscCall(MatGetOwnershipRange(M, &first, &end));
  PetscCall(VecGetArrayRead(system.scale, &s));
  PetscCall(VecGetArray(system.diagonal, &d));
  PetscReal q = 0;
  PetscInt longest = 0;
  PetscCall(forEachLocalRow(
      M, [&](PetscInt row, PetscInt count, const PetscInt* columns, const PetscScalar* values) {
        PetscReal offDiagonal = 0, onDiagonal = 0;
        for (PetscInt k = 0; k < count; ++k) {
          if (columns[k] == row) {
            onDiagonal = values[k];
          } else if (!inR || (*inR)[static_cast<size_t>(columns[k])]) {
            offDiagonal += std::abs(values[k]);
          }
        }
        longest = std::max(longest, count);
        for (PetscInt j = 0; j < components; ++j) {  // (interleaved channels: the same row of M)
          const PetscInt at = (row - first) * components + j;
          d[at] = 1 - s[at] * onDiagonal;
          q = std::max(q, s[at] * offDiagonal / d[at]);
        }
      }));
  PetscCall(VecRestoreArray(system.diagonal, &d));
  PetscCall(VecRestoreArrayRead(system.scale, &s));
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(M));
  PetscCallMPI(MPIU_Allreduce(&q, &system.contraction, 1, MPIU_REAL, MPIU_MAX, comm));
  PetscCallMPI(MPIU_Allreduce(&longest, &system.longestRow, 1, MPIU_INT, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode scatterSolution(const ChannelSystem& system, Vec emission, Vec B) {
  PetscFunctionBeginUser;
  if (system.reflective) {
    PetscCall(VecCopy(emission, B));
    PetscCall(VecISCopy(B, system.reflective, SCATTER_FORWARD, system.solution));
  } else {
    PetscCall(VecCopy(system.solution, B));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode channelResidual(const ChannelSystem& system, Vec x, Vec r, WorkCount& work) {
  OwnedVec product;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(x, product.out()));
  PetscCall(MatMult(system.matrix, x, product));
  ++work.matrixProducts;
  work.nonzeroProducts += system.nonzeros;
  PetscCall(VecPointwiseMult(product, system.scale, product));
  PetscCall(VecWAXPY(r, 1.0, product, system.rhs));  // b + s ⊙ M x
  PetscCall(VecAXPY(r, -1.0, x));                    // − x
  PetscFunctionReturn(0);
}

PetscErrorCode relativeErrorBound(const ChannelSystem& system, Vec r, Vec x, PetscReal* bound) {
  OwnedVec scaled;
  PetscReal scaledNorm, solutionNorm, rhsNorm, smallestDiagonal;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(r, scaled.out()));
  PetscCall(VecPointwiseDivide(scaled, r, system.diagonal));
  PetscCall(VecNorm(scaled, NORM_INFINITY, &scaledNorm));
  PetscCall(normOnR(system, x, NORM_INFINITY, &solutionNorm));
  PetscCall(normOnR(system, system.rhs, NORM_INFINITY, &rhsNorm));
  PetscCall(VecMin(system.diagonal, nullptr, &smallestDiagonal));
  scaled.reset();
  const PetscReal terms = static_cast<PetscReal>(system.longestRow + 2) * PETSC_MACHINE_EPSILON;
  const PetscReal roundOff =
      terms / (1 - terms) * (rhsNorm + (1 + system.contraction) * solutionNorm) / smallestDiagonal;
  if (system.contraction >= 1 || smallestDiagonal <= 0) {
    *bound = std::numeric_limits<PetscReal>::infinity();
  } else {
    const PetscReal absolute = (scaledNorm + roundOff) / (1 - system.contraction);
    *bound = solutionNorm > 0 ? absolute / solutionNorm : absolute;
  }
  PetscFunctionReturn(0);
}

void HistoryRecorder::record(int64_t iteration, double residualNorm) const {
  if (!history) return;
  const double seconds = MPI_Wtime() - start;
  const double residual = normalise > 0 ? residualNorm / normalise : residualNorm;
  const std::vector<int> channels = together.empty() ? std::vector<int>{channel} : together;
  for (int c : channels) {
    history->channel.push_back(c);
    history->iteration.push_back(iteration);
    history->residual.push_back(residual);
    history->seconds.push_back(seconds);
  }
  // Long solves show where they are (every rank calls this alike; the caller prints rank 0's).
  if (progress && *progress && seconds - lastProgress >= kProgressSeconds) {
    lastProgress = seconds;
    std::string names;
    for (int c : channels)
      names += std::string(names.empty() ? "" : ", ") + channelName(c, channelCount);
    char line[200];
    std::snprintf(line, sizeof line,
                  "  solve: %s%s: iteration %lld, relative residual %.3g, %.0f s", names.c_str(),
                  channels.size() > 1 ? " together" : "", static_cast<long long>(iteration),
                  residual, seconds);
    (*progress)(line);
  }
}

}  // namespace radiosity::solve
