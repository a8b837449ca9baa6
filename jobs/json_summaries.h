// The --json summaries of `verify` and of a failed command (`solve`'s is run/solve_json.h, `info`'s
// io/store's describeResultJson): one
// JSON document on stdout per run, its layout in docs/json-summaries.md. Each document names its
// schema ("radiosity.solve/1"), so that a script can tell a layout it knows.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/store/result.h"
#include "jobs/commands.h"
#include "jobs/verify_report.h"

namespace radiosity::jobs {

/// What `verify` measured; `exitCode` is its verdict (kOk or kFailure).
std::string verifyJson(const VerifySettings& settings, int64_t patches, int64_t reflecting,
                       int64_t sampled, const Measures& channels, bool hasStderr,
                       const std::string& cappedNote, int exitCode);

/// A command that failed: its exit code and message (docs/refusals.md), so that a script
/// reading stdout gets a document whatever happened.
std::string failureJson(const std::string& command, int exitCode, const std::string& message);

}  // namespace radiosity::jobs
