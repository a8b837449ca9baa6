// PETSc's life around the program: starting and ending it with MPI, the stages of the
// -log_view report, and the options nobody asked for.
#include <malloc.h>
#include <petscsys.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "solve/petsc_check.h"
#include "solve/runtime.h"

namespace radiosity::solve {

// Debian's SuperLU_DIST, which PETSc loads, turns off in its library constructor glibc's mmap for
// large blocks and the return of freed memory (mallopt(M_MMAP_MAX, 0) and M_TRIM_THRESHOLD -1).
// Every array then comes from the brk heap and every byte ever freed stays resident, so a run
// kept the sum of its rounds' and stages' peaks (9.3 GB a rank where F was 3.2 GB, 10^6 patches).
// Blocks from 32 MiB (F's store, PETSc's vectors at scale) are mapped again and go back when
// freed. The heap of smaller blocks is left as it is: trimming it costs the sampling's many
// short-lived tallies a quarter of the form-factor stage's time in fresh pages.
void returnFreedMemory() {
  mallopt(M_MMAP_MAX, 65536);  // glibc's default
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
}

// The heap's free pages go back to the system where a stage has let go of its work and another
// is about to take its own: glibc no longer trims by itself (above), and F's store, the biggest
// next thing, is mapped apart and cannot reuse them. Not during sampling (the note above).
// Measured at 10^6 patches, 32 samples, 2 ranks: the peak 808 -> 775 MB a rank.
void releaseFreedHeap() { malloc_trim(0); }

Runtime::Runtime(int argc, char** argv) {
  returnFreedMemory();
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
  releaseFreedHeap();
}

ScopedStage::~ScopedStage() {
  PetscLogStagePop();
  releaseFreedHeap();
}

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
