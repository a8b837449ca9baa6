// `verify`'s measures (jobs/verify_report.h) on samples made by hand: the measured error's
// quantiles over resamples of the patches drawn, and the verdict's warning when --tol lies
// between them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "jobs/console.h"
#include "jobs/verify_report.h"
#include "mpi_environment.h"

namespace radiosity::jobs {
namespace {

// `count` grey patches of unit area and B_ref = 1, each with relative error `errors[k]` (the
// last value repeated), no reference noise.
std::vector<Sampled> sampleWithErrors(const std::vector<double>& errors, size_t count) {
  std::vector<Sampled> sample;
  for (size_t k = 0; k < count; ++k) {
    const double error = errors[std::min(k, errors.size() - 1)];
    Sampled s{static_cast<int64_t>(k), 1.0, {0.5, 0.5, 0.5}, {0, 0, 0}, {}, {}, {1, 1, 1}, {}};
    for (int c = 0; c < 3; ++c) s.radiosity[c] = 1 + error;
    sample.push_back(s);
  }
  return sample;
}

TEST(VerifyMeasures, AnErrorTheSameOnEveryPatchIsKnownExactly) {
  const Measures m = measureChannels(sampleWithErrors({0.03}, 200), 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(m[c].corrected, 0.03, 1e-12);
    EXPECT_NEAR(m[c].correctedLow, 0.03, 1e-12);
    EXPECT_NEAR(m[c].correctedHigh, 0.03, 1e-12);
  }
}

// One patch in 200 with 100 % error, the rest 1 %: the RMS is 0.0714, but a sample of 200
// misses that patch about a third of the time (0.01) and holds it three times one time in
// twelve (0.123): the quantiles say so.
TEST(VerifyMeasures, AHeavyTailWidensTheQuantilesAroundTheMeasuredError) {
  std::vector<double> errors(200, 0.01);
  errors[57] = 1.0;
  const Measures m = measureChannels(sampleWithErrors(errors, 200), 3);
  EXPECT_NEAR(m[0].corrected, std::sqrt((199 * 1e-4 + 1) / 200), 1e-12);
  EXPECT_NEAR(m[0].correctedLow, 0.01, 1e-9);
  EXPECT_GT(m[0].correctedHigh, 0.1);
  EXPECT_LT(m[0].correctedLow, m[0].corrected);
  EXPECT_GT(m[0].correctedHigh, m[0].corrected);
  // The same on every call (and so on every rank): the generator is fixed.
  const Measures again = measureChannels(sampleWithErrors(errors, 200), 3);
  EXPECT_EQ(again[0].correctedLow, m[0].correctedLow);
  EXPECT_EQ(again[0].correctedHigh, m[0].correctedHigh);
}

std::string warningsOfVerdict(const Measures& m, double tol, int* exitCode) {
  VerifySettings settings;
  settings.tol = tol;
  ::testing::internal::CaptureStderr();
  *exitCode = verdict(Console(MPI_COMM_WORLD), settings, m, "");
  return ::testing::internal::GetCapturedStderr();
}

TEST(VerifyVerdict, WarnsWhereTolLiesBetweenTheQuantilesOfThePatchesDrawn) {
  std::vector<double> errors(200, 0.01);
  errors[57] = 1.0;
  const Measures m = measureChannels(sampleWithErrors(errors, 200), 3);
  int exitCode = -1;
  // 0.05: below the measured 0.0714 (a failure), but inside the quantiles: uncertain.
  std::string warnings = warningsOfVerdict(m, 0.05, &exitCode);
  EXPECT_EQ(exitCode, 1);
  EXPECT_NE(warnings.find("give more --patches"), std::string::npos) << warnings;
  // 0.5: above every resample: a clear pass, no warning.
  warnings = warningsOfVerdict(m, 0.5, &exitCode);
  EXPECT_EQ(exitCode, 0);
  EXPECT_EQ(warnings.find("give more --patches"), std::string::npos) << warnings;
  // An error the same everywhere: no uncertainty from the patches drawn.
  warnings = warningsOfVerdict(measureChannels(sampleWithErrors({0.03}, 200), 3), 0.05, &exitCode);
  EXPECT_EQ(exitCode, 0);
  EXPECT_EQ(warnings.find("give more --patches"), std::string::npos) << warnings;
}

}  // namespace
}  // namespace radiosity::jobs
