// Checks of what the ranks hand the result writer, made before the file is created so that bad
// arguments fail on all ranks together.
#include "io/store/result_checks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/store/hdf5_read.h"
#include "io/store/rank_blocks.h"

namespace radiosity {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

/// The error estimates of this rank's patches: one row per patch wherever any rank has them
/// (`withStderr`, `withDiscretisation`), each value finite, the standard error ≥ 0.
void checkErrorEstimates(const LocalSolution& local, bool withStderr, bool withDiscretisation) {
  if (withStderr && local.radiosityStderr.size() != local.radiosity.size())
    fail("radiosity stderr has " + std::to_string(local.radiosityStderr.size()) +
         " rows, radiosity " + std::to_string(local.radiosity.size()) +
         " (some rank has a radiosity stderr, so every rank needs one row per patch it owns)");
  for (size_t i = 0; i < local.radiosityStderr.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double e = local.radiosityStderr[i][k];
      if (!std::isfinite(e) || !(e >= 0))
        fail("radiosity stderr of patch " + std::to_string(local.firstPatch + int64_t(i)) +
             " channel " + std::to_string(k) + " is " + h5::exact(e) + ", not a finite value >= 0");
    }
  if (withDiscretisation && local.radiosityDiscretisation.size() != local.radiosity.size())
    fail("radiosity discretisation error has " +
         std::to_string(local.radiosityDiscretisation.size()) + " rows, radiosity " +
         std::to_string(local.radiosity.size()));
  for (size_t i = 0; i < local.radiosityDiscretisation.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(local.radiosityDiscretisation[i][k]))
        fail("radiosity discretisation error of patch " +
             std::to_string(local.firstPatch + int64_t(i)) + " channel " + std::to_string(k) +
             " is not finite");
}

/// Rows of F from `firstRow`, `rowCount` of them: those of this rank's patches.
void checkRowsArePatches(int64_t firstRow, int64_t rowCount, const LocalSolution& local) {
  const auto count = static_cast<int64_t>(local.radiosity.size());
  if (firstRow != local.firstPatch || rowCount != count)
    fail("rows of F " + std::to_string(firstRow) + " + " + std::to_string(rowCount) +
         " do not match the patches " + std::to_string(local.firstPatch) + " + " +
         std::to_string(count));
}

/// This rank's rows of F: the rows of its patches, in CSR form, of columns in [0, np).
void checkFormFactorRows(const SparseRows& rows, const LocalSolution& local, int64_t np) {
  checkRowsArePatches(rows.firstRow, rows.rowCount(), local);
  if (rows.rowStart.front() != 0 || rows.rowStart.back() != rows.nonzeros() ||
      rows.value.size() != rows.column.size() ||
      !std::is_sorted(rows.rowStart.begin(), rows.rowStart.end()))
    fail("rows of F are not in CSR form: row starts from " + std::to_string(rows.rowStart.front()) +
         " to " + std::to_string(rows.rowStart.back()) + " for " +
         std::to_string(rows.column.size()) + " columns and " + std::to_string(rows.value.size()) +
         " values");
  for (int64_t j : rows.column)
    if (j < 0 || j >= np)
      fail("a row of F has column " + std::to_string(j) + " of " + std::to_string(np));
}

/// The same of F's store: its rows, none given back, of columns in [0, np).
void checkFormFactorStore(const SplitRows& store, const LocalSolution& local, int64_t np) {
  checkRowsArePatches(store.firstRow, store.rowCount(), local);
  if (store.releasedRows > 0) fail("rows of F were given back before the result was written");
  for (int64_t r = 0; r < store.rowCount(); ++r)
    store.forEachInColumnOrder(r, [&](int64_t j, double) {
      if (j < 0 || j >= np)
        fail("a row of F has column " + std::to_string(j) + " of " + std::to_string(np));
    });
}

}  // namespace

int anyHiddenPatch(MPI_Comm comm, const LocalSolution& local) {
  int any = std::find(local.hidden.begin(), local.hidden.end(), 1) != local.hidden.end() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

bool checkResultArguments(h5::CollectiveSteps& steps, MPI_Comm comm, const Mesh& patches,
                          const LocalSolution& local, const SparseRows* rows,
                          const SplitRows* store) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  int64_t mine[4] = {local.firstPatch, static_cast<int64_t>(local.radiosity.size()), np, nv};
  std::vector<int64_t> all(4 * static_cast<size_t>(size));
  MPI_Allgather(mine, 4, MPI_INT64_T, all.data(), 4, MPI_INT64_T, comm);
  const int given = rows != nullptr || store != nullptr ? 1 : 0;
  int withRows[2] = {given, given};
  MPI_Allreduce(MPI_IN_PLACE, &withRows[0], 1, MPI_INT, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &withRows[1], 1, MPI_INT, MPI_MAX, comm);
  int withStderr = local.radiosityStderr.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &withStderr, 1, MPI_INT, MPI_MAX, comm);
  int withDiscretisation = local.radiosityDiscretisation.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &withDiscretisation, 1, MPI_INT, MPI_MAX, comm);
  const int withHidden = anyHiddenPatch(comm, local);

  steps.run([&] {
    if (local.irradiance.size() != local.radiosity.size())
      fail("irradiance has " + std::to_string(local.irradiance.size()) + " rows, radiosity " +
           std::to_string(local.radiosity.size()));
    if (patches.sourceFace.size() != patches.triangles.size() ||
        patches.reflectance.size() != patches.triangles.size() ||
        patches.emission.size() != patches.triangles.size())
      fail("mesh has " + std::to_string(np) + " triangles but " +
           std::to_string(patches.sourceFace.size()) + " source faces, " +
           std::to_string(patches.reflectance.size()) + " reflectances and " +
           std::to_string(patches.emission.size()) + " emissions");
    const auto sameMesh = [&](int r, const int64_t* theirs) {
      if (theirs[2] != np || theirs[3] != nv)
        fail("rank " + std::to_string(r) + " holds a mesh of " + std::to_string(theirs[2]) +
             " patches and " + std::to_string(theirs[3]) + " vertices, rank " +
             std::to_string(rank) + " one of " + std::to_string(np) + " and " + std::to_string(nv));
    };
    checkRankBlocksTile(all, 4, np, {"owns patches", "own", "patches"}, sameMesh);
    for (int64_t t = local.firstPatch; t < local.firstPatch + mine[1]; ++t)
      for (int k = 0; k < 3; ++k)
        if (patches.triangles[t][k] < 0 || patches.triangles[t][k] >= nv)
          fail("triangle " + std::to_string(t) + " refers to vertex " +
               std::to_string(patches.triangles[t][k]) + " of " + std::to_string(nv));
    checkErrorEstimates(local, withStderr != 0, withDiscretisation != 0);
    if (withHidden != 0 && local.hidden.size() != local.radiosity.size())
      fail("hidden flags for " + std::to_string(local.hidden.size()) + " patches, radiosity " +
           std::to_string(local.radiosity.size()));
    if (withRows[0] != withRows[1]) fail("some ranks have rows of F to write, others not");
    if (rows != nullptr && store != nullptr) fail("rows of F given twice, as rows and as store");
    if (rows != nullptr) checkFormFactorRows(*rows, local, np);
    if (store != nullptr) checkFormFactorStore(*store, local, np);
  });
  return withStderr != 0;
}

}  // namespace radiosity
