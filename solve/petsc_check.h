// Private to solve/: a failed PETSc call turned into the exception the program reports, for the
// C++ entry points that call PETSc-style functions (those return PetscErrorCode).
#pragma once

#include <petscsys.h>

#include <string>

#include "core/error.h"

namespace radiosity::solve {

inline void check(PetscErrorCode code, const char* what) {
  if (code) {
    throw Error(exit_code::kFailure,
                std::string("PETSc failed in ") + what + " (error " + std::to_string(code) + ")");
  }
}

}  // namespace radiosity::solve
