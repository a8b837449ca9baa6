// Rank-aware output and collective failure handling for the program's commands.
#pragma once

#include <mpi.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "run/log_file.h"

namespace radiosity::run {

/// Prints on rank 0 only (deal.II's pcout), as a Unix tool does: what a command is run for (a
/// report, a description, help) to stdout, the log of how it went to stderr, warnings and errors
/// to stderr always.
class Console {
 public:
  explicit Console(MPI_Comm comm);
  /// The same console without the log (-q): info() prints nothing; results, warnings and
  /// errors still do.
  Console quietened() const {
    Console quiet = *this;
    quiet.quiet_ = true;
    return quiet;
  }
  bool isQuiet() const { return quiet_; }
  /// The same console for --json: the JSON document is what the command is for (json(), on
  /// stdout), so result() lines join the log on stderr.
  Console forJson() const {
    Console json = *this;
    json.json_ = true;
    return json;
  }
  bool isJson() const { return json_; }
  /// The same console for -v: detail() lines join the log.
  Console verbose() const {
    Console detailed = *this;
    detailed.verbose_ = true;
    return detailed;
  }
  bool isVerbose() const { return verbose_; }
  /// The same console writing its log, warnings and results to `log` too (--log-file), even
  /// when quietened.
  Console loggingTo(std::shared_ptr<LogFile> log) const {
    Console logged = *this;
    logged.log_ = std::move(log);
    return logged;
  }
  /// The log file, if any (shared by the copies of this console).
  LogFile* logFile() const { return log_.get(); }
  bool isRoot() const { return rank_ == 0; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  MPI_Comm comm() const { return comm_; }
  /// A line of the log (stderr), unless quietened.
  void info(const std::string& line) const;
  /// A line of the log only with -v: the inner figures a user rarely needs.
  void detail(const std::string& line) const {
    if (verbose_) info(line);
  }
  /// A line of what the command is for (stdout, quiet or not; with --json a log line).
  void result(const std::string& line) const;
  /// The --json document (stdout).
  void json(const std::string& document) const;
  void warn(const std::string& line) const;

 private:
  MPI_Comm comm_;  ///< not owned
  int rank_ = 0, ranks_ = 1;
  bool quiet_ = false;
  bool json_ = false;
  bool verbose_ = false;
  std::shared_ptr<LogFile> log_;  ///< rank 0's, where given
};

/// Wall time of a stage, the slowest rank's (collective).
double slowestRank(MPI_Comm comm, double seconds);

}  // namespace radiosity::run
