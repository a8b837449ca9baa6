// What the PETSc stage's tests (solve_test.cpp, solve_repair_test.cpp) share: this rank's place,
// sampled problems on the refined box and the Cornell box, the whole matrix gathered on every
// rank, and the checks of its rows.
#pragma once

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "sampled_form_factors.h"
#include "test_scenes.h"

namespace radiosity::testing {

inline int rank(MPI_Comm comm = MPI_COMM_WORLD) {
  int r;
  MPI_Comm_rank(comm, &r);
  return r;
}
inline int ranks(MPI_Comm comm = MPI_COMM_WORLD) {
  int n;
  MPI_Comm_size(comm, &n);
  return n;
}

// A scene's patches and the rows of F that one rank of `comm` owns.
struct Problem {
  Mesh patches;
  formfactor::SparseRows rows;
  std::vector<double> area;  ///< of the rows
};

inline Problem sample(const Mesh& patches, int64_t rays, MPI_Comm comm = MPI_COMM_WORLD) {
  Problem p;
  p.patches = patches;
  partition::PatchRange owned =
      partition::blockOf(patches.triangleCount(), rank(comm), ranks(comm));
  trace::SceneTracer tracer(patches);
  formfactor::Statistics statistics;
  formfactor::Options options;
  options.raysPerPatch = rays;
  options.seed = 5;
  p.rows =
      testing::sampledFormFactors(tracer, patches, owned.begin, owned.end, options, statistics);
  for (int64_t i = owned.begin; i < owned.end; ++i) p.area.push_back(patches.area(i));
  return p;
}

inline Mesh refinedBox() {
  return partition::orderAlongCurve(partition::refine(testing::closedBox(0.5, 1.0), 0.02));
}

inline Mesh cornell() {
  Mesh scene = loadScene("builtin:cornell");
  return partition::orderAlongCurve(partition::refine(scene, scene.totalArea() / 600));
}

// Every rank's rows, on every rank.
inline formfactor::SparseRows gather(const formfactor::SparseRows& rows,
                                     MPI_Comm comm = MPI_COMM_WORLD) {
  const int n = ranks(comm);
  std::vector<int> rowCounts(n), entryCounts(n), rowOffsets(n, 0), entryOffsets(n, 0);
  int myRows = static_cast<int>(rows.rowCount()), myEntries = static_cast<int>(rows.nonzeros());
  MPI_Allgather(&myRows, 1, MPI_INT, rowCounts.data(), 1, MPI_INT, comm);
  MPI_Allgather(&myEntries, 1, MPI_INT, entryCounts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < n; ++r) {
    rowOffsets[r] = rowOffsets[r - 1] + rowCounts[r - 1];
    entryOffsets[r] = entryOffsets[r - 1] + entryCounts[r - 1];
  }
  std::vector<int64_t> lengths(rows.rowCount());
  for (int64_t r = 0; r < rows.rowCount(); ++r)
    lengths[r] = rows.rowStart[r + 1] - rows.rowStart[r];
  std::vector<int64_t> allLengths(rowOffsets[n - 1] + rowCounts[n - 1]);
  MPI_Allgatherv(lengths.data(), myRows, MPI_INT64_T, allLengths.data(), rowCounts.data(),
                 rowOffsets.data(), MPI_INT64_T, comm);
  formfactor::SparseRows all;
  const int total = entryOffsets[n - 1] + entryCounts[n - 1];
  all.column.resize(total);
  all.value.resize(total);
  MPI_Allgatherv(rows.column.data(), myEntries, MPI_INT64_T, all.column.data(), entryCounts.data(),
                 entryOffsets.data(), MPI_INT64_T, comm);
  MPI_Allgatherv(rows.value.data(), myEntries, MPI_DOUBLE, all.value.data(), entryCounts.data(),
                 entryOffsets.data(), MPI_DOUBLE, comm);
  for (int64_t length : allLengths) all.rowStart.push_back(all.rowStart.back() + length);
  return all;
}

inline double rowSum(const formfactor::SparseRows& rows, int64_t r) {
  double sum = 0;
  for (int64_t k = rows.rowStart[r]; k < rows.rowStart[r + 1]; ++k) sum += rows.value[k];
  return sum;
}

// F_ij of a whole matrix (0 where not stored); columns are sorted.
inline double entry(const formfactor::SparseRows& rows, int64_t i, int64_t j) {
  auto begin = rows.column.begin() + rows.rowStart[i],
       end = rows.column.begin() + rows.rowStart[i + 1];
  auto found = std::lower_bound(begin, end, j);
  return found != end && *found == j ? rows.value[found - rows.column.begin()] : 0.0;
}

// max |A_i F_ij − A_j F_ji| / max S over the whole matrix.
inline double reciprocityError(const formfactor::SparseRows& all, const Mesh& patches) {
  double largest = 0, error = 0;
  for (int64_t i = 0; i < all.rowCount(); ++i) {
    for (int64_t k = all.rowStart[i]; k < all.rowStart[i + 1]; ++k) {
      const int64_t j = all.column[k];
      const double sij = patches.area(i) * all.value[k], sji = patches.area(j) * entry(all, j, i);
      largest = std::max(largest, sij);
      error = std::max(error, std::abs(sij - sji));
    }
  }
  return error / largest;
}

inline void expectSortedPositiveRows(const formfactor::SparseRows& all) {
  for (int64_t i = 0; i < all.rowCount(); ++i) {
    for (int64_t k = all.rowStart[i]; k < all.rowStart[i + 1]; ++k) {
      EXPECT_GT(all.value[k], 0.0) << "F(" << i << ", " << all.column[k] << ")";
      if (k > all.rowStart[i]) {
        EXPECT_LT(all.column[k - 1], all.column[k]);
      }
    }
  }
}

// The threshold below which about `share` of the nonzeros lie (ties: the smallest value above).
inline double thresholdFor(const formfactor::SparseRows& all, double share) {
  std::vector<double> values = all.value;
  std::sort(values.begin(), values.end());
  return std::nextafter(values[static_cast<size_t>(share * values.size())], 2.0);
}

}  // namespace radiosity::testing
