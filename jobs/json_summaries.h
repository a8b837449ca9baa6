// The --json summaries of `solve` and `verify` (`info`'s is io/store's describeResultJson): one
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

/// A thermal run's figures for one table of its boundary conditions, as the log lists them.
struct SurfaceHeat {
  std::string name;  ///< the table's name, "[default]" for the default's
  bool temperatureGiven = true;
  double area = 0;                               ///< m²
  double heatRate = 0, heatRateError = 0;        ///< W, leaving the surface
  double temperature = 0, temperatureError = 0;  ///< K: the given one, or the mean (area-weighted)
};

/// A thermal run's heat rates per table and its balance Σ q A.
struct HeatSummary {
  std::vector<SurfaceHeat> surfaces;
  double balance = 0;                  ///< W
  double balanceShare = 0;             ///< of Σ |q A|
  double surroundingsTemperature = 0;  ///< K, where the balance goes
};

/// What a finished solve reports: the file written, its attributes and the run's measures.
struct SolveSummary {
  std::string output;  ///< empty: --mesh-only, nothing written
  int64_t patches = 0;
  const ResultAttributes* attributes = nullptr;  ///< not owned
  std::map<std::string, double> peakMegabytes;   ///< by stage, the largest rank's
  const HeatSummary* heat = nullptr;             ///< a thermal run's; not owned
};

std::string solveJson(const SolveSummary& summary);

/// What `verify` measured; `exitCode` is its verdict (kOk or kFailure).
std::string verifyJson(const VerifySettings& settings, int64_t patches, int64_t reflecting,
                       int64_t sampled, const Measures& channels, bool hasStderr,
                       const std::string& cappedNote, int exitCode);

/// A command that failed: its exit code and message (docs/refusals.md), so that a script
/// reading stdout gets a document whatever happened.
std::string failureJson(const std::string& command, int exitCode, const std::string& message);

}  // namespace radiosity::jobs
