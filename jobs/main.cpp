// radiosity: diffuse global illumination as one linear system, on any number of MPI ranks.
//
// Sample runs:
//   mpirun -n 2 build/radiosity solve builtin:cornell -o cornell.h5
//   build/radiosity render cornell.h5 -o cornell.png
//   mpirun -n 4 build/radiosity solve room.obj --max-area 0.01 --rays 4096 -log_view
#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/shown_text.h"
#include "jobs/commands.h"
#include "solve/solve.h"

namespace {

// PETSc options are written with one dash and a letter (-ksp_type gmres, -log_view); ours
// with two dashes or are -o/-h. A PETSc option takes the next word as its value unless that
// word is an option itself or one of ours (isOurWord).
bool isPetscOption(const std::string& word) {
  return word.size() > 2 && word[0] == '-' && std::isalpha(static_cast<unsigned char>(word[1]));
}

bool isOptionWord(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && !std::isdigit(static_cast<unsigned char>(word[1])) &&
         word[1] != '.';
}

bool endsWith(const std::string& word, const std::string& end) {
  return word.size() >= end.size() && word.compare(word.size() - end.size(), end.size(), end) == 0;
}

// A word that is ours even after a PETSc option: a command (before any), a built-in scene, or
// a file of a kind the commands read (a scene, a result, a job or boundary-condition file). So
// `solve -ksp_monitor room.obj` solves room.obj instead of giving it to -ksp_monitor.
bool isOurWord(const std::string& word, bool commandSeen) {
  static const char* const commands[] = {"solve", "render", "study", "info",
                                         "scene", "verify", "xdmf",  "export"};
  if (!commandSeen)
    for (const char* command : commands)
      if (word == command) return true;
  if (word.rfind("builtin:", 0) == 0) return true;
  std::string lower = word;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* end : {".obj", ".ply", ".off", ".stl", ".vs3", ".h5", ".hdf5", ".toml"})
    if (endsWith(lower, end)) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> ours, petscWords;
  std::vector<char*> petsc{argv[0]};
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (!isPetscOption(word)) {
      ours.push_back(word);
      continue;
    }
    petsc.push_back(argv[i]);
    petscWords.push_back(word);
    if (i + 1 < argc && !isOptionWord(argv[i + 1]) && !isOurWord(argv[i + 1], !ours.empty()))
      petsc.push_back(argv[++i]);
  }
  petsc.push_back(nullptr);

  int code = radiosity::exit_code::kFailure;
  try {
    radiosity::solve::Runtime runtime(static_cast<int>(petsc.size()) - 1, petsc.data());
    radiosity::run::Console console(MPI_COMM_WORLD);
    try {
      code = radiosity::jobs::runCommandLine(ours, console, petscWords);
      // A misspelt PETSc option would otherwise be ignored without a word.
      if (code == radiosity::exit_code::kOk) {
        for (const std::string& option : radiosity::solve::unusedPetscOptions())
          console.warn("PETSc option " + option +
                       " was not used (misspelt, or for a solver "
                       "that did not run)");
      }
    } catch (const radiosity::Error& e) {
      // Errors that reach here were agreed by all ranks (runCollectively or collective code).
      // A stop that was asked for (--stop-after, a scheduler's signal) saved the run's state: it
      // says so, without "error".
      code = e.exitCode();
      if (console.isRoot())
        std::fprintf(stderr, "%s\n", radiosity::failureLine(code, e.what()).c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n",
                 radiosity::failureLine(radiosity::exit_code::kFailure, e.what()).c_str());
  }
  return code;
}
