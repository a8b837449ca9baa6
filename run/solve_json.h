// `radiosity solve --json`'s summary: one JSON document on stdout per run, its layout in
// docs/json-summaries.md, naming its schema ("radiosity.solve/1") so that a script can tell a
// layout it knows. (`verify`'s and a failure's are jobs/json_summaries.h.)
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/store/result.h"

namespace radiosity::run {

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

}  // namespace radiosity::run
