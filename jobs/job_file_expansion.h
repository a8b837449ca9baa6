// `--config FILE` on the command line: the job file's options (jobs/job_file.h) put in its place,
// and a value CLI11 then refuses traced back to the job file's line.
#pragma once

#include <CLI/CLI.hpp>

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace radiosity::jobs {

/// Where each option of the job file came from, so that a value CLI11 refuses is reported with
/// the file and line (exit 3, bad input) rather than as a usage error without them.
struct JobFileOrigin {
  std::string file;                                               ///< empty: no job file
  std::map<std::string, std::pair<long, std::string>> lineOfKey;  ///< "--key" → line, value
  std::set<std::string> alsoOnCommandLine;                        ///< "--key"
};

/// The arguments with the job file expanded, and where its options came from.
struct ExpandedArguments {
  std::vector<std::string> arguments;
  JobFileOrigin origin;
};

/// Replaces `--config FILE` by the options the job file holds, placed first so that options on
/// the command line override them. Keys must name options of `command` (InputError otherwise);
/// a second --config is a usage error.
ExpandedArguments expandJobFile(const std::vector<std::string>& arguments, const CLI::App& command);

/// Throws CLI11's refusal `message` as InputError at the job file's line when the message names
/// an option of the job file and, if the command line gives that option too, quotes the job
/// file's value; as a usage error otherwise.
[[noreturn]] void throwParseRefusal(const std::string& message, const JobFileOrigin& origin);

}  // namespace radiosity::jobs
