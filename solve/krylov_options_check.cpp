// The PETSc options of the main solve tried before any work: a KSP set up from them on a
// one-row system, so that a misspelt type or a malformed value (-pc_type bogus, -ksp_max_it x)
// is refused before the form factors are sampled, not after, when they would be lost.
#include <string>

#include "core/error.h"
#include "solve/petsc_handles.h"
#include "solve/runtime.h"

namespace radiosity::solve {

namespace {

PetscErrorCode setUpFromOptions() {
  OwnedMat identity;
  OwnedKsp ksp;
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, 1, 1, 1, nullptr, identity.out()));
  PetscCall(MatSetValue(identity, 0, 0, 1.0, INSERT_VALUES));
  PetscCall(MatAssemblyBegin(identity, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(identity, MAT_FINAL_ASSEMBLY));
  PetscCall(KSPCreate(PETSC_COMM_SELF, ksp.out()));
  PetscCall(KSPSetOperators(ksp, identity, identity));
  PetscCall(KSPSetType(ksp, KSPGMRES));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(KSPSetUp(ksp));
  PetscFunctionReturn(0);
}

}  // namespace

void checkKrylovOptions() {
  // PETSc's own handler would print a trace for a user's typo: the message is ours to give.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode code = setUpFromOptions();
  PetscPopErrorHandler();
  if (code == 0) return;
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  std::string why = specific != nullptr && *specific != '\0' ? specific
                    : text != nullptr                        ? text
                                                             : "error " + std::to_string(code);
  throw Error(exit_code::kUsage, "the PETSc options for the solve cannot be used: " + why +
                                     " (nothing was done; -help lists PETSc's options)");
}

}  // namespace radiosity::solve
