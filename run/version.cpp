#include "run/version.h"

#include <hdf5.h>
#include <mpi.h>
#include <petscsys.h>

#include "formfactor/formfactor.h"

#ifndef RADIOSITY_VERSION
#define RADIOSITY_VERSION "unknown"
#endif
#ifndef RADIOSITY_GIT_REVISION
#define RADIOSITY_GIT_REVISION "unknown"
#endif

namespace radiosity::run {

std::map<std::string, std::string> softwareVersions() {
  std::map<std::string, std::string> versions;
  versions["radiosity"] = std::string(RADIOSITY_VERSION) + " (git " + RADIOSITY_GIT_REVISION + ")";
  versions["petsc"] = std::to_string(PETSC_VERSION_MAJOR) + "." +
                      std::to_string(PETSC_VERSION_MINOR) + "." +
                      std::to_string(PETSC_VERSION_SUBMINOR);
  versions["embree"] = trace::embreeVersion();
  unsigned major = 0, minor = 0, release = 0;
  if (H5get_libversion(&major, &minor, &release) >= 0)
    versions["hdf5"] =
        std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(release);
  char library[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  int length = 0;
  if (MPI_Get_library_version(library, &length) == MPI_SUCCESS) {
    std::string text(library, static_cast<size_t>(length));
    versions["mpi"] = text.substr(0, text.find_first_of(",\n"));
  }
  return versions;
}

std::string versionText() {
  std::map<std::string, std::string> versions = softwareVersions();
  std::string text = "radiosity " + versions["radiosity"] + "\n";
  versions.erase("radiosity");
  for (const auto& [name, version] : versions) text += "  " + name + " " + version + "\n";
  return text;
}

}  // namespace radiosity::run
