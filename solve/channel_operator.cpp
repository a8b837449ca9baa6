// The channel operator A = I − diag(s) M_R as a PETSc shell matrix, and the shell over an
// explicit matrix: both count their products (WorkCount), which the report gives in place of
// time.
#include <memory>

#include "solve/channel_system.h"
#include "solve/petsc_handles.h"

namespace radiosity::solve {

namespace {

// A PETSc shell that counts its products: with `scale`, the channel operator
// y = x − s ⊙ (M x); without, the plain product y = K x of an explicit matrix.
struct ShellContext {
  Mat matrix = nullptr;
  Vec scale = nullptr, diagonal = nullptr;  ///< null for a plain product
  PetscInt nonzeros = 0;
  WorkCount* work = nullptr;
  OwnedVec product;  ///< with scale: M x
};

PetscErrorCode shellMult(Mat A, Vec x, Vec y) {
  ShellContext* context;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &context));
  PetscCall(MatMult(context->matrix, x, context->scale ? context->product : y));
  ++context->work->matrixProducts;
  context->work->nonzeroProducts += context->nonzeros;
  if (context->scale) {
    PetscCall(VecPointwiseMult(context->product, context->scale, context->product));
    PetscCall(VecWAXPY(y, -1.0, context->product, x));  // y = x − s ⊙ (M x)
  }
  PetscFunctionReturn(0);
}

PetscErrorCode shellDiagonal(Mat A, Vec d) {
  ShellContext* context;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &context));
  if (context->diagonal) {
    PetscCall(VecCopy(context->diagonal, d));
  } else {
    PetscCall(MatGetDiagonal(context->matrix, d));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode shellDestroy(void* raw) {
  delete static_cast<ShellContext*>(raw);
  return 0;
}

// The shell over `context` (owned by the shell once it is made), shaped like its matrix.
PetscErrorCode createShell(std::unique_ptr<ShellContext> context, Mat* A) {
  MPI_Comm comm;
  PetscInt localRows, localColumns, rows, columns;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(context->matrix), &comm));
  PetscCall(MatGetLocalSize(context->matrix, &localRows, &localColumns));
  PetscCall(MatGetSize(context->matrix, &rows, &columns));
  PetscCall(MatCreateShell(comm, localRows, localColumns, rows, columns, context.get(), A));
  PetscCall(MatShellSetContextDestroy(*A, shellDestroy));
  context.release();  // the shell's now
  PetscCall(MatShellSetOperation(*A, MATOP_MULT, reinterpret_cast<void (*)(void)>(shellMult)));
  PetscCall(MatShellSetOperation(*A, MATOP_GET_DIAGONAL,
                                 reinterpret_cast<void (*)(void)>(shellDiagonal)));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode createShellOperator(const ChannelSystem& system, WorkCount& work, Mat* A) {
  auto context = std::make_unique<ShellContext>();
  context->matrix = system.matrix;
  context->scale = system.scale;
  context->diagonal = system.diagonal;
  context->nonzeros = system.nonzeros;
  context->work = &work;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(system.rhs, context->product.out()));
  PetscCall(createShell(std::move(context), A));
  PetscFunctionReturn(0);
}

PetscErrorCode createCountingOperator(Mat K, PetscInt nonzeros, WorkCount& work, Mat* A) {
  auto context = std::make_unique<ShellContext>();
  context->matrix = K;
  context->nonzeros = nonzeros;
  context->work = &work;
  PetscFunctionBeginUser;
  PetscCall(createShell(std::move(context), A));
  PetscFunctionReturn(0);
}

}  // namespace radiosity::solve
