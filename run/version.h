// What made this program and its results: its version and git revision, and the versions of the
// libraries it runs on, for `--version` and the result file's root attributes (software_<name>),
// so that a result can say what computed it.
#pragma once

#include <map>
#include <string>

namespace radiosity::run {

/// name → version: radiosity ("0.2.0 (git <describe>)"), petsc, embree, hdf5, mpi (the MPI
/// library's own words, first line). Needs MPI initialised (for the MPI library's version).
std::map<std::string, std::string> softwareVersions();

/// `radiosity --version`: a line per entry of softwareVersions(), the program first.
std::string versionText();

}  // namespace radiosity::run
