// A fresh directory for one test, the same on every rank: made by rank 0, its name shared, and
// removed (after every rank is done with it) when the test ends; and the files in it.
#pragma once

#include <mpi.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "mpi_environment.h"

namespace radiosity::testing {

class SharedTempDir {
 public:
  /// `prefix` names the test program in the directory's name. Collective.
  explicit SharedTempDir(const std::string& prefix) {
    std::string name;
    if (worldRank() == 0) {
      std::string pattern =
          (std::filesystem::temp_directory_path() / (prefix + ".XXXXXX")).string();
      if (mkdtemp(pattern.data()) != nullptr) name = pattern;
    }
    int length = static_cast<int>(name.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
    name.resize(length);
    MPI_Bcast(name.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
    path_ = name;
  }
  ~SharedTempDir() {
    MPI_Barrier(MPI_COMM_WORLD);
    std::error_code ignored;
    if (worldRank() == 0 && !path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  SharedTempDir(const SharedTempDir&) = delete;
  SharedTempDir& operator=(const SharedTempDir&) = delete;

  /// Empty if the directory could not be made.
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The names of the files in `dir`: what a test left there.
inline std::set<std::string> namesIn(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.insert(entry.path().filename());
  return names;
}

/// Writes `text` to `path`, replacing what was there.
inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace radiosity::testing
