// What the unit tests of the radiosity_jobs library (jobs_test.cpp, jobs_files_test.cpp,
// request_options_test.cpp, run_control_test.cpp) share: a temporary file, the error a call throws,
// and a command line parsed on one rank.
#pragma once

#include <gtest/gtest.h>
#include <mpi.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "jobs/command_line.h"
#include "run/console.h"

namespace radiosity::jobs {

/// A file in the temporary folder, named for the process, removed with the test.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("jobs_test_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

/// The Error `work` throws (failing the test if none), for its exit code and message.
inline Error thrownBy(const std::function<void()>& work) {
  try {
    work();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no radiosity::Error thrown";
  return Error(-1, "");
}

/// `arguments` parsed as the program parses its command line.
inline CommandLine parse(const std::vector<std::string>& arguments) {
  const run::Console console(MPI_COMM_WORLD);
  return parseCommandLine(arguments, console);
}

}  // namespace radiosity::jobs
