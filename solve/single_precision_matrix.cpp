#include "solve/single_precision_matrix.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

#include "solve/petsc_handles.h"

namespace radiosity::solve {

namespace {

constexpr const char* kMarker = "RadiositySinglePrecision_C";

using OwnedScatter = Handle<VecScatter, VecScatterDestroy>;

// What the one-channel shell and its k-channel ones share: the store and the global ids of the
// off-diagonal block's columns (PETSc's garray), ascending.
struct Store {
  SplitRows* rows = nullptr;
  std::vector<PetscInt> ghosts;
  PetscInt localNonzeros = 0;
  // Rows stored once a pair (SplitRows::pairsOnce): F_ji = F_ij A_i / A_j of each stored F_ij,
  // and F_ii: the row's rest less what its mirrors bring (the closed forms' disagreement between
  // the two ways of a pair, about 1e-9 of it), so that each row of F adds up to its sum.
  bool pairs = false;
  std::vector<double> area;      ///< the rows' areas
  std::vector<double> diagonal;  ///< F_ii
};

struct Context {
  std::shared_ptr<Store> store;
  PetscInt components = 1;
  OwnedScatter scatter;  ///< x's entries at the ghost columns, k per column, into ghostValues
  OwnedVec ghostValues;
  std::vector<PetscInt> rowColumns;  ///< MatGetRow's answer
  std::vector<PetscScalar> rowValues;
  // Pairs: the mirrors' part of a product, the rank's own columns and the ghosts' (sent home by
  // the scatter in reverse), and A x.
  OwnedVec mirrors, ghostMirrors;
  std::vector<PetscScalar> weighted;
};

// Numbers the off-diagonal block's columns by their place among the distinct ones, in place,
// and gives those ids ascending: a bit per patch, and a count per 64 patches, find the place
// without a second array of F's size.
std::vector<PetscInt> numberGhosts(SplitRows::Block& block, PetscInt patches) {
  std::vector<uint64_t> seen(static_cast<size_t>(patches) / 64 + 1, 0);
  for (int32_t j : block.column) seen[static_cast<size_t>(j) >> 6] |= uint64_t{1} << (j & 63);
  std::vector<int32_t> before(seen.size() + 1, 0);
  std::vector<PetscInt> ghosts;
  for (size_t w = 0; w < seen.size(); ++w) {
    before[w + 1] = before[w] + std::popcount(seen[w]);
    for (uint64_t bits = seen[w]; bits != 0; bits &= bits - 1)
      ghosts.push_back(static_cast<PetscInt>(64 * w + static_cast<size_t>(std::countr_zero(bits))));
  }
  for (int32_t& j : block.column) {
    const size_t w = static_cast<size_t>(j) >> 6;
    const uint64_t below = (uint64_t{1} << (j & 63)) - 1;
    j = before[w] + std::popcount(seen[w] & below);
  }
  return ghosts;
}

// y (+)= B x over the block's rows, k channels interleaved: each value read once for all k.
// Summed as PETSc sums, so that the product is its matrix's of the same values bit for bit: one
// channel from y, entry by entry (MatMultAdd_SeqAIJ); k channels from 0, then added to y
// (MatMultAdd_SeqMAIJ_k).
template <int K>
void multiplyRows(const SplitRows::Block& block, PetscInt rowCount, const PetscScalar* x,
                  PetscScalar* y, bool add) {
  const int32_t* start = block.rowStart.data();
  const int32_t* column = block.column.data();
  const float* value = block.singleValue.data();
  for (PetscInt r = 0; r < rowCount; ++r) {
    PetscScalar* yr = y + static_cast<size_t>(r) * K;
    double sum[K];
    const bool fromY = add && K == 1;
    for (int c = 0; c < K; ++c) sum[c] = fromY ? yr[c] : 0.0;
    for (int32_t e = start[r]; e < start[r + 1]; ++e) {
      const double v = value[e];
      const PetscScalar* xj = x + static_cast<size_t>(column[e]) * K;
      for (int c = 0; c < K; ++c) sum[c] += v * xj[c];
    }
    for (int c = 0; c < K; ++c) yr[c] = add && !fromY ? yr[c] + sum[c] : sum[c];
  }
}

void multiplyRows(PetscInt k, const SplitRows::Block& block, PetscInt rowCount,
                  const PetscScalar* x, PetscScalar* y, bool add) {
  if (k == 1) {
    multiplyRows<1>(block, rowCount, x, y, add);
  } else if (k == 2) {
    multiplyRows<2>(block, rowCount, x, y, add);
  } else {
    multiplyRows<3>(block, rowCount, x, y, add);
  }
}

// z += Fᵀ w over the block's stored entries, k channels interleaved: each entry F_rc adds
// F_rc w_r to column c.
template <int K>
void mirrorRows(const SplitRows::Block& block, PetscInt rowCount, const PetscScalar* w,
                PetscScalar* z) {
  const int32_t* start = block.rowStart.data();
  const int32_t* column = block.column.data();
  const float* value = block.singleValue.data();
  for (PetscInt r = 0; r < rowCount; ++r) {
    const PetscScalar* wr = w + static_cast<size_t>(r) * K;
    for (int32_t e = start[r]; e < start[r + 1]; ++e) {
      const double v = value[e];
      PetscScalar* zc = z + static_cast<size_t>(column[e]) * K;
      for (int c = 0; c < K; ++c) zc[c] += v * wr[c];
    }
  }
}

void mirrorRows(PetscInt k, const SplitRows::Block& block, PetscInt rowCount, const PetscScalar* w,
                PetscScalar* z) {
  if (k == 1) {
    mirrorRows<1>(block, rowCount, w, z);
  } else if (k == 2) {
    mirrorRows<2>(block, rowCount, w, z);
  } else {
    mirrorRows<3>(block, rowCount, w, z);
  }
}

// context->mirrors = A⁻¹ times what `spread(z, zGhost)` puts at each column (k per row): the
// rank's own columns into z, the others' into zGhost, which the forward scatter run in reverse
// sends home, combined by `combine` (ADD_VALUES for the product's sums, MAX_VALUES for maxima).
template <typename Spread>
PetscErrorCode gatherMirrors(Context* context, PetscInt k, InsertMode combine, Spread spread) {
  const Store& store = *context->store;
  const auto count = static_cast<PetscInt>(store.rows->rowCount());
  PetscScalar *z, *zGhost;
  PetscFunctionBeginUser;
  PetscCall(VecSet(context->mirrors, 0));
  PetscCall(VecSet(context->ghostMirrors, 0));
  PetscCall(VecGetArray(context->mirrors, &z));
  PetscCall(VecGetArray(context->ghostMirrors, &zGhost));
  spread(z, zGhost);
  PetscCall(VecRestoreArray(context->ghostMirrors, &zGhost));
  PetscCall(VecRestoreArray(context->mirrors, &z));
  PetscCall(VecScatterBegin(context->scatter, context->ghostMirrors, context->mirrors, combine,
                            SCATTER_REVERSE));
  PetscCall(VecScatterEnd(context->scatter, context->ghostMirrors, context->mirrors, combine,
                          SCATTER_REVERSE));
  PetscCall(VecGetArray(context->mirrors, &z));
  for (PetscInt r = 0; r < count; ++r)
    for (PetscInt c = 0; c < k; ++c) z[r * k + c] /= store.area[r];
  PetscCall(VecRestoreArray(context->mirrors, &z));
  PetscFunctionReturn(0);
}

// context->mirrors = (F_mirrored x): A⁻¹ Sᵀ (A x) over the stored pairs, S the stored entries.
PetscErrorCode mirrorPart(Context* context, Vec x) {
  const Store& store = *context->store;
  const SplitRows& rows = *store.rows;
  const PetscInt k = context->components, count = static_cast<PetscInt>(rows.rowCount());
  const PetscScalar* in;
  PetscFunctionBeginUser;
  context->weighted.resize(static_cast<size_t>(count * k));
  PetscCall(VecGetArrayRead(x, &in));
  for (PetscInt r = 0; r < count; ++r)
    for (PetscInt c = 0; c < k; ++c) context->weighted[r * k + c] = store.area[r] * in[r * k + c];
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscCall(gatherMirrors(context, k, ADD_VALUES, [&](PetscScalar* z, PetscScalar* zGhost) {
    mirrorRows(k, rows.diagonalBlock, count, context->weighted.data(), z);
    mirrorRows(k, rows.offDiagonalBlock, count, context->weighted.data(), zGhost);
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode mult(Mat M, Vec x, Vec y) {
  Context* context;
  const PetscScalar *in, *ghost;
  PetscScalar* out;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  const SplitRows& rows = *context->store->rows;
  const PetscInt k = context->components, count = static_cast<PetscInt>(rows.rowCount());
  PetscCall(
      VecScatterBegin(context->scatter, x, context->ghostValues, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(x, &in));
  PetscCall(VecGetArray(y, &out));
  multiplyRows(k, rows.diagonalBlock, count, in, out, false);  // (while the ghosts travel)
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscCall(
      VecScatterEnd(context->scatter, x, context->ghostValues, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(context->ghostValues, &ghost));
  multiplyRows(k, rows.offDiagonalBlock, count, ghost, out, true);
  PetscCall(VecRestoreArrayRead(context->ghostValues, &ghost));
  PetscCall(VecRestoreArray(y, &out));
  if (!context->store->pairs) PetscFunctionReturn(0);
  // The pairs the other rows hold, and F_ii.
  const std::vector<double>& diagonal = context->store->diagonal;
  const PetscScalar* mirrored;
  PetscCall(mirrorPart(context, x));
  PetscCall(VecGetArrayRead(x, &in));
  PetscCall(VecGetArrayRead(context->mirrors, &mirrored));
  PetscCall(VecGetArray(y, &out));
  for (PetscInt r = 0; r < count; ++r)
    for (PetscInt c = 0; c < k; ++c)
      out[r * k + c] += mirrored[r * k + c] + diagonal[r] * in[r * k + c];
  PetscCall(VecRestoreArray(y, &out));
  PetscCall(VecRestoreArrayRead(context->mirrors, &mirrored));
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscFunctionReturn(0);
}

PetscErrorCode getDiagonal(Mat M, Vec d) {
  Context* context;
  PetscScalar* out;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  const SplitRows& rows = *context->store->rows;
  const SplitRows::Block& own = rows.diagonalBlock;
  const PetscInt k = context->components;
  PetscCall(VecGetArray(d, &out));
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    double diagonal = 0;
    for (int32_t e = own.rowStart[r]; e < own.rowStart[r + 1]; ++e)
      if (own.column[e] == r) diagonal = own.singleValue[e];
    if (context->store->pairs) diagonal = context->store->diagonal[static_cast<size_t>(r)];
    for (PetscInt c = 0; c < k; ++c) out[r * k + c] = diagonal;
  }
  PetscCall(VecRestoreArray(d, &out));
  PetscFunctionReturn(0);
}

// context->mirrors = each row's largest mirrored entry, max_j F_ji A_j / A_i (one channel).
PetscErrorCode mirrorMaxima(Context* context) {
  const Store& store = *context->store;
  const SplitRows& rows = *store.rows;
  const auto count = static_cast<PetscInt>(rows.rowCount());
  PetscFunctionBeginUser;
  PetscCall(gatherMirrors(context, 1, MAX_VALUES, [&](PetscScalar* z, PetscScalar* zGhost) {
    for (const auto& [block, into] :
         {std::pair{&rows.diagonalBlock, z}, {&rows.offDiagonalBlock, zGhost}})
      for (PetscInt r = 0; r < count; ++r)
        for (int32_t e = block->rowStart[r]; e < block->rowStart[r + 1]; ++e) {
          PetscScalar& m = into[block->column[e]];
          m = std::max(m, std::abs(static_cast<double>(block->singleValue[e])) * store.area[r]);
        }
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode getRowMaxAbs(Mat M, Vec v, PetscInt index[]) {
  Context* context;
  PetscScalar* out;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  const SplitRows& rows = *context->store->rows;
  PetscCheck(context->components == 1, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "row maxima of F's one-channel matrix only");
  const Store& store = *context->store;
  PetscCheck(!store.pairs || !index, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "rows stored once a pair: their maxima's columns are not kept");
  if (store.pairs) PetscCall(mirrorMaxima(context));
  const PetscScalar* mirrored = nullptr;
  if (store.pairs) PetscCall(VecGetArrayRead(context->mirrors, &mirrored));
  PetscCall(VecGetArray(v, &out));
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    double largest = 0;
    int64_t at = rows.firstRow + r;
    rows.forEachInColumnOrder(r, [&](int64_t j, double value) {
      if (store.pairs && j == rows.firstRow + r) value = store.diagonal[static_cast<size_t>(r)];
      if (std::abs(value) > largest) largest = std::abs(value), at = j;
    });
    out[r] = mirrored ? std::max(largest, mirrored[r]) : largest;
    if (index) index[r] = static_cast<PetscInt>(at);
  }
  PetscCall(VecRestoreArray(v, &out));
  if (mirrored) PetscCall(VecRestoreArrayRead(context->mirrors, &mirrored));
  PetscFunctionReturn(0);
}

PetscErrorCode getRow(Mat M, PetscInt row, PetscInt* count, PetscInt** columns,
                      PetscScalar** values) {
  Context* context;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  const SplitRows& rows = *context->store->rows;
  PetscCheck(
      context->components == 1 && row >= rows.firstRow && row < rows.firstRow + rows.rowCount(),
      PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "row %" PetscInt_FMT " is not this rank's", row);
  PetscCheck(!context->store->pairs, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "rows stored once a pair are not read whole (their mirrors are other ranks')");
  context->rowColumns.clear();
  context->rowValues.clear();
  rows.forEachInColumnOrder(row - rows.firstRow, [&](int64_t j, double value) {
    context->rowColumns.push_back(static_cast<PetscInt>(j));
    context->rowValues.push_back(value);
  });
  if (count) *count = static_cast<PetscInt>(context->rowColumns.size());
  if (columns) *columns = context->rowColumns.data();
  if (values) *values = context->rowValues.data();
  PetscFunctionReturn(0);
}

PetscErrorCode restoreRow(Mat, PetscInt, PetscInt*, PetscInt**, PetscScalar**) { return 0; }

PetscErrorCode getInfo(Mat M, MatInfoType type, MatInfo* info) {
  Context* context;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  auto nonzeros = static_cast<PetscLogDouble>(context->store->localNonzeros);
  std::memset(info, 0, sizeof *info);
  if (type != MAT_LOCAL) {
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &nonzeros, 1, MPIU_PETSCLOGDOUBLE,
                                type == MAT_GLOBAL_SUM ? MPI_SUM : MPI_MAX,
                                PetscObjectComm(reinterpret_cast<PetscObject>(M))));
  }
  info->nz_used = info->nz_allocated = nonzeros;
  info->block_size = static_cast<PetscLogDouble>(context->components);
  PetscFunctionReturn(0);
}

PetscErrorCode destroyContext(void* context) {
  delete static_cast<Context*>(context);
  return 0;
}

void marker() {}

PetscErrorCode createShell(MPI_Comm comm, std::shared_ptr<Store> store, PetscInt k, Mat* M) {
  const SplitRows& rows = *store->rows;
  const auto local = static_cast<PetscInt>(rows.rowCount()) * k;
  auto context = std::make_unique<Context>();
  context->store = store;
  context->components = k;
  Context* raw = context.get();
  OwnedVec x;
  OwnedIs ghostIds;
  PetscFunctionBeginUser;
  PetscCheck(k >= 1 && k <= 3, comm, PETSC_ERR_SUP, "%" PetscInt_FMT " channels: 1 to 3 only", k);
  PetscCall(MatCreateShell(comm, local, local, PETSC_DETERMINE, PETSC_DETERMINE, raw, M));
  PetscCall(MatShellSetContextDestroy(*M, destroyContext));
  context.release();  // the shell's now
  PetscCall(MatSetBlockSizes(*M, k, k));
  const auto op = [&](MatOperation operation, auto function) {
    return MatShellSetOperation(*M, operation, reinterpret_cast<void (*)(void)>(function));
  };
  PetscCall(op(MATOP_MULT, mult));
  PetscCall(op(MATOP_GET_DIAGONAL, getDiagonal));
  PetscCall(op(MATOP_GET_ROW_MAX_ABS, getRowMaxAbs));
  PetscCall(op(MATOP_GET_ROW, getRow));
  PetscCall(op(MATOP_RESTORE_ROW, restoreRow));
  PetscCall(op(MATOP_GETINFO, getInfo));
  PetscCall(PetscObjectComposeFunction(reinterpret_cast<PetscObject>(*M), kMarker, marker));
  // The ghosts' values: k for each distinct column of the off-diagonal block.
  const auto ghosts = static_cast<PetscInt>(store->ghosts.size());
  PetscCall(MatCreateVecs(*M, x.out(), nullptr));
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, k, ghosts, store->ghosts.data(), PETSC_USE_POINTER,
                          ghostIds.out()));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, ghosts * k, raw->ghostValues.out()));
  PetscCall(VecScatterCreate(x, ghostIds, raw->ghostValues, nullptr, raw->scatter.out()));
  if (store->pairs) {
    PetscCall(VecDuplicate(x, raw->mirrors.out()));
    PetscCall(VecDuplicate(raw->ghostValues, raw->ghostMirrors.out()));
  }
  PetscFunctionReturn(0);
}

// F_ii of rows stored once a pair: the row's rest less its mirrors' sum (the product with 1).
PetscErrorCode settleDiagonal(Mat M) {
  Context* context;
  OwnedVec ones;
  const PetscScalar* mirrored;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(M, &context));
  Store& store = *context->store;
  PetscCall(MatCreateVecs(M, ones.out(), nullptr));
  PetscCall(VecSet(ones, 1));
  PetscCall(mirrorPart(context, ones));
  PetscCall(VecGetArrayRead(context->mirrors, &mirrored));
  store.diagonal.resize(store.area.size());
  for (size_t r = 0; r < store.area.size(); ++r)
    store.diagonal[r] = store.rows->pairRest[r] - mirrored[r];
  PetscCall(VecRestoreArrayRead(context->mirrors, &mirrored));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode createSinglePrecisionMatrix(MPI_Comm comm, SplitRows& rows,
                                           const std::vector<double>& area, Mat* M) {
  PetscFunctionBeginUser;
  PetscCheck(
      rows.singlePrecision && rows.endRow - rows.firstRow == rows.rowCount() && !rows.columnMap,
      comm, PETSC_ERR_ARG_WRONG,
      "the store must hold its rows whole in single precision, with global columns");
  if constexpr (!std::is_same_v<PetscInt, int32_t>) {
    SETERRQ(comm, PETSC_ERR_SUP, "F's store in single precision needs PETSc's 32-bit indices");
  } else {
    auto store = std::make_shared<Store>();
    store->rows = &rows;
    PetscInt patches = 0;
    const auto local = static_cast<PetscInt>(rows.rowCount());
    PetscCallMPI(MPIU_Allreduce(&local, &patches, 1, MPIU_INT, MPI_SUM, comm));
    store->ghosts = numberGhosts(rows.offDiagonalBlock, patches);
    store->localNonzeros = static_cast<PetscInt>(rows.diagonalBlock.column.size() +
                                                 rows.offDiagonalBlock.column.size());
    store->pairs = rows.pairsOnce;
    if (store->pairs) {  // (each stored entry twice, the diagonal slots once)
      PetscCheck(area.size() == static_cast<size_t>(rows.rowCount()), comm, PETSC_ERR_ARG_SIZ,
                 "rows stored once a pair need the rows' areas");
      store->area = area;
      store->localNonzeros = 2 * store->localNonzeros - local;
    }
    rows.columnMap = store->ghosts.data();  // (takeRowsBack numbers them globally again)
    PetscCall(createShell(comm, store, 1, M));
    if (store->pairs) PetscCall(settleDiagonal(*M));
  }
  PetscFunctionReturn(0);
}

bool holdsPairsOnce(Mat M) {
  if (!isSinglePrecisionMatrix(M)) return false;
  Context* context = nullptr;
  PetscCallAbort(PETSC_COMM_SELF, MatShellGetContext(M, &context));
  return context->store->pairs;
}

bool isSinglePrecisionMatrix(Mat M) {
  void (*found)(void) = nullptr;
  PetscCallAbort(PETSC_COMM_SELF,
                 PetscObjectQueryFunction(reinterpret_cast<PetscObject>(M), kMarker, &found));
  return found != nullptr;
}

PetscErrorCode createSinglePrecisionComponents(Mat M, PetscInt k, Mat* block) {
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(M));
  Context* context;
  PetscFunctionBeginUser;
  PetscCheck(isSinglePrecisionMatrix(M), comm, PETSC_ERR_ARG_WRONG,
             "not a matrix of F's single-precision store");
  PetscCall(MatShellGetContext(M, &context));
  PetscCall(createShell(comm, context->store, k, block));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
