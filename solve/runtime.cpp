// PETSc's life around the program: starting and ending it with MPI, the stages of the
// -log_view report, and the options nobody asked for.
#include <petscsys.h>

#include <csignal>
#include <map>
#include <string>

#include "solve/petsc_check.h"
#include "solve/solve.h"

namespace radiosity::solve {

Runtime::Runtime(int argc, char** argv) {
  check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
  // A closed pipe (`radiosity info x.h5 | head`) ends the program quietly, as for any tool,
  // instead of PETSc's handler reporting a crash and aborting MPI.
  std::signal(SIGPIPE, SIG_DFL);
}

Runtime::~Runtime() { PetscFinalize(); }

ScopedStage::ScopedStage(const char* name) {
  // Stages are registered once per name and pushed again on later uses.
  static std::map<std::string, PetscLogStage> stages;
  auto found = stages.find(name);
  if (found == stages.end()) {
    PetscLogStage stage;
    check(PetscLogStageRegister(name, &stage), "PetscLogStageRegister");
    found = stages.emplace(name, stage).first;
  }
  check(PetscLogStagePush(found->second), "PetscLogStagePush");
}

ScopedStage::~ScopedStage() { PetscLogStagePop(); }

std::vector<std::string> unusedPetscOptions() {
  PetscInt count = 0;
  char **names = nullptr, **values = nullptr;
  check(PetscOptionsLeftGet(nullptr, &count, &names, &values), "PetscOptionsLeftGet");
  std::vector<std::string> unused;
  for (PetscInt k = 0; k < count; ++k) unused.push_back(std::string("-") + names[k]);
  check(PetscOptionsLeftRestore(nullptr, &count, &names, &values), "PetscOptionsLeftRestore");
  return unused;
}

}  // namespace radiosity::solve
