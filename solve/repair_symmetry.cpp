// How far the estimated S = diag(A) F is from symmetric, its symmetric part and how far a
// repair moved it: each walks this rank's rows of two matrices together, with no communication
// but the sums.
#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solve/repair_steps.h"

namespace radiosity::solve {

namespace {

// Calls visit(row, column, x_ij, y_ij) for every (row, column) stored in X or in Y (the other
// one 0), over this rank's rows, columns ascending. X and Y have the same layout.
template <class Visit>
PetscErrorCode walkRows(Mat X, Mat Y, Visit&& visit) {
  PetscInt first, end;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(X, &first, &end));
  for (PetscInt row = first; row < end; ++row) {
    PetscInt nx, ny;
    const PetscInt *cx, *cy;
    const PetscScalar *vx, *vy;
    PetscCall(MatGetRow(X, row, &nx, &cx, &vx));
    PetscCall(MatGetRow(Y, row, &ny, &cy, &vy));
    for (PetscInt kx = 0, ky = 0; kx < nx || ky < ny;) {
      if (ky == ny || (kx < nx && cx[kx] < cy[ky])) {
        visit(row, cx[kx], vx[kx], 0.0);
        ++kx;
      } else if (kx == nx || cy[ky] < cx[kx]) {
        visit(row, cy[ky], 0.0, vy[ky]);
        ++ky;
      } else {
        visit(row, cx[kx], vx[kx], vy[ky]);
        ++kx;
        ++ky;
      }
    }
    PetscCall(MatRestoreRow(Y, row, &ny, &cy, &vy));
    PetscCall(MatRestoreRow(X, row, &nx, &cx, &vx));
  }
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode measureDefect(MPI_Comm comm, Mat S, Mat St, Defect* defect) {
  double sums[4] = {0, 0, 0, 0};  // Σ (S_ij − S_ji)², Σ S_ij², one-sided nonzeros, nonzeros
  double maxima[2] = {0, 0};      // max pair defect, max S_ij
  PetscFunctionBeginUser;
  PetscCall(walkRows(S, St, [&](PetscInt, PetscInt, double a, double b) {
    sums[0] += (a - b) * (a - b);
    sums[1] += a * a;
    maxima[1] = std::max(maxima[1], a);
    if (a == 0) return;
    sums[3] += 1;
    if (b == 0) {
      sums[2] += 1;
    } else {
      maxima[0] = std::max(maxima[0], std::abs(a - b) / std::max(a, b));
    }
  }));
  PetscCall(allReduce(comm, sums, 4, MPI_SUM));
  PetscCall(allReduce(comm, maxima, 2, MPI_MAX));
  defect->relative = sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) : 0;
  defect->oneSided = sums[3] > 0 ? sums[2] / sums[3] : 0;
  defect->maxPair = maxima[0];
  defect->largest = maxima[1];
  PetscFunctionReturn(0);
}

PetscErrorCode symmetricPart(MPI_Comm comm, Mat S, Mat St, Mat* out) {
  PetscInt first, end;
  std::vector<PetscInt> rowStart{0}, columns;
  std::vector<PetscScalar> values;
  PetscInt lastRow;
  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(S, &first, &end));
  lastRow = first;
  PetscCall(walkRows(S, St, [&](PetscInt row, PetscInt column, double a, double b) {
    for (; lastRow < row; ++lastRow) rowStart.push_back(static_cast<PetscInt>(columns.size()));
    columns.push_back(column);
    values.push_back((a + b) * 0.5);
  }));
  for (; lastRow < end; ++lastRow) rowStart.push_back(static_cast<PetscInt>(columns.size()));
  PetscCall(MatCreateMPIAIJWithArrays(comm, end - first, end - first, PETSC_DETERMINE,
                                      PETSC_DETERMINE, rowStart.data(), columns.data(),
                                      values.data(), out));
  PetscFunctionReturn(0);
}

PetscErrorCode relativeChange(MPI_Comm comm, Mat S, Mat raw, double* change) {
  double sums[2] = {0, 0};
  PetscFunctionBeginUser;
  PetscCall(walkRows(S, raw, [&](PetscInt, PetscInt, double a, double b) {
    sums[0] += (a - b) * (a - b);
    sums[1] += b * b;
  }));
  PetscCall(allReduce(comm, sums, 2, MPI_SUM));
  *change = sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) : 0;
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
