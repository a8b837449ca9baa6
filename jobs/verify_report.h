// What `radiosity verify` reports once the reference is traced (jobs/verify_command.cpp): the
// measured error of the result per channel against its own estimate, the worst patches, the CSV
// of the sample and the verdict against --tol.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/vec3.h"
#include "jobs/commands.h"
#include "run/console.h"

namespace radiosity::jobs {

/// One sampled patch: the result's values and the reference.
struct Sampled {
  int64_t patch;
  double area;
  Rgb rho, emission, radiosity, radiosityStderr, reference, referenceStderr;
};

/// The measures of one channel over the sampled patches that reflect in it.
struct ChannelMeasures {
  int64_t patches = 0;
  double meanReference = 0;  ///< area-weighted
  double measured = 0, noise = 0, corrected = 0;
  /// How far `corrected` could be off for having drawn these patches and not others: its 5 % and
  /// 95 % quantiles over the sample resampled with replacement (kSampleResamples times, by a
  /// fixed generator: the same on every rank and run). Wide where a few patches carry most of
  /// the error, as on refined meshes with their heavy tails.
  double correctedLow = 0, correctedHigh = 0;
  double estimate = 0, coverage = 0;  ///< only with /patches/radiosity_stderr
};

/// Resamples of the sampled patches behind ChannelMeasures' interval.
inline constexpr int kSampleResamples = 2000;

/// The measures of the result's channels: 3 (red, green, blue), or 1 for a thermal result,
/// whose channels are alike and which is reported as one, "grey" (the others then have none).
struct Measures : std::array<ChannelMeasures, 3> {
  int count = 3;
  const char* name(int c) const { return channelName(c, count); }
};

/// Each of the result's `count` channels' measures over the sample (every rank holds the whole
/// sample).
Measures measureChannels(const std::vector<Sampled>& sample, int count);

/// The table of the measures; `hasStderr`: the result holds its own error estimate.
void printMeasures(const run::Console& console, const Measures& channels, bool hasStderr);

/// The patches with the largest relative error in their worst channel.
void printWorstPatches(const run::Console& console, const std::vector<Sampled>& sample,
                       const Measures& channels);

/// The sample as CSV, a row per patch and channel (of `count`), values in full.
std::string csvOf(const std::vector<Sampled>& sample, bool hasStderr, int count);

/// How far the file's estimate may be from the measured error before verify says so: a factor
/// beyond what the patches drawn allow (their 5 % / 95 % quantiles).
inline constexpr double kEstimateSlack = 2.0;
/// The least coverage (share of patches within 2 sigma; about 95 % for honest sigmas) that
/// verify accepts of a file's per-patch estimate.
inline constexpr double kLeastCoverage = 0.75;

/// What verify finds wrong with a channel's own error estimate: empty where nothing is.
struct EstimateCheck {
  std::string understated;  ///< the estimate too low (a failure): why, with the figures
  std::string overstated;   ///< far too high (a warning)
};
EstimateCheck checkEstimate(const ChannelMeasures& m);

/// Says whether the measured error (noise taken out) is within --tol in every channel and, with
/// `hasStderr`, whether the file's own estimate covers it (checkEstimate), and returns the exit
/// code: kOk, or kFailure for either. Warns where --tol lies inside a channel's interval from
/// the sample (too few --patches to tell), the reference's noise is above half of --tol or of
/// the error it measures (too few --paths), or the estimate is far above the error.
/// `cappedNote`, if not empty, says the reference was cut short at --max-bounces.
int verdict(const run::Console& console, const VerifySettings& settings, const Measures& channels,
            const std::string& cappedNote, bool hasStderr);

/// `x` by the printf `format`.
std::string number(double x, const char* format = "%.4g");

}  // namespace radiosity::jobs
