// Running build/radiosity as users do, `mpiexec -n R radiosity ...`, from a test: to the end,
// or in the background to be signalled like a scheduler would.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace radiosity::testing {

struct ProgramRun {
  int exitCode;
  std::string output;  ///< stdout and stderr
};

/// The shell command for `radiosity ARGUMENTS` on `ranks` ranks, output to `log`: mpiexec as
/// CMake's FindMPI describes it (tests/CMakeLists.txt). Open MPI's run-as-root and
/// oversubscription are asked for in the environment, which other MPIs ignore.
/// `launcher` goes between the environment and mpiexec ("exec" to replace the shell).
/// `errorLog`: stderr's file, apart from stdout's `log`; empty: both in `log`.
inline std::string programCommand(int ranks, const std::string& arguments, const std::string& log,
                                  const std::string& environment = "",
                                  const std::string& launcher = "",
                                  const std::string& errorLog = "") {
  const std::string mpiexec = std::string(MPIEXEC) + " " + MPIEXEC_NUMPROC_FLAG + " " +
                              std::to_string(ranks) + " " + MPIEXEC_PREFLAGS + " " +
                              RADIOSITY_BINARY + " " + MPIEXEC_POSTFLAGS;
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_rmaps_base_oversubscribe=1 " +
         environment + " " + launcher + " " + mpiexec + " " + arguments + " > " + log +
         (errorLog.empty() ? " 2>&1" : " 2> " + errorLog);
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs to the end.
inline ProgramRun runProgram(int ranks, const std::string& arguments, const std::string& log,
                             const std::string& environment = "") {
  const int status = std::system(programCommand(ranks, arguments, log, environment).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(log)};
}

/// What a run printed on stdout and on stderr, apart.
struct SplitRun {
  int exitCode;
  std::string out, err;
};

/// Runs to the end with stdout to `outPath` and stderr to `errPath`.
inline SplitRun runProgramSplit(int ranks, const std::string& arguments, const std::string& outPath,
                                const std::string& errPath) {
  const int status =
      std::system(programCommand(ranks, arguments, outPath, "", "", errPath).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(outPath), readText(errPath)};
}

/// A run in the background: mpiexec, in a process group of its own with its ranks.
class BackgroundRun {
 public:
  BackgroundRun(int ranks, const std::string& arguments, const std::string& log,
                const std::string& environment = "")
      : log_(log) {
    const std::string command = programCommand(ranks, arguments, log, environment, "exec");
    pid_ = fork();
    if (pid_ == 0) {
      setpgid(0, 0);
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    setpgid(pid_, pid_);
  }
  ~BackgroundRun() {
    if (pid_ > 0 && !finished_) {
      kill(-pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  BackgroundRun(const BackgroundRun&) = delete;
  BackgroundRun& operator=(const BackgroundRun&) = delete;

  /// Sends `signal` to mpiexec only (it forwards SIGUSR1/SIGTERM to the ranks) or, with
  /// `wholeGroup`, to mpiexec and every rank at once (as `kill -9` of a job would).
  void signal(int number, bool wholeGroup = false) const {
    kill(wholeGroup ? -pid_ : pid_, number);
  }
  /// Polls `ready` every 10 ms for up to `seconds`; false if it never held or the run ended.
  template <class Condition>
  bool waitUntil(Condition ready, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      if (ready()) return true;
      if (!finished_ && waitpid(pid_, &status_, WNOHANG) == pid_) finished_ = true;
      if (finished_) return ready();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  /// Waits for the end: the exit code of mpiexec and the log.
  ProgramRun wait() {
    if (!finished_) waitpid(pid_, &status_, 0);
    finished_ = true;
    return {WIFEXITED(status_) ? WEXITSTATUS(status_) : -1, readText(log_)};
  }
  pid_t pid() const { return pid_; }

 private:
  std::string log_;
  pid_t pid_ = -1;
  int status_ = 0;
  bool finished_ = false;
};

}  // namespace radiosity::testing
