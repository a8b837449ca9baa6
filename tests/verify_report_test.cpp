// `verify`'s measures (jobs/verify_report.h) on samples made by hand: the measured error's
// quantiles over resamples of the patches drawn, and the verdict's warning when --tol lies
// between them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "jobs/verify_report.h"
#include "mpi_environment.h"
#include "run/console.h"

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
  *exitCode = verdict(run::Console(MPI_COMM_WORLD), settings, m, "", false);
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

// `count` grey patches of unit area, B_ref = 1 with reference noise `noise`, the result off by
// `error` and stating `estimate` as its standard error.
std::vector<Sampled> sampleWithEstimate(double error, double estimate, double noise, size_t count) {
  std::vector<Sampled> sample = sampleWithErrors({error}, count);
  for (Sampled& s : sample)
    for (int c = 0; c < 3; ++c) {
      s.radiosityStderr[c] = estimate;
      s.referenceStderr[c] = noise;
    }
  return sample;
}

std::string verdictWithEstimate(const Measures& m, int* exitCode, int64_t paths = 16384) {
  VerifySettings settings;
  settings.tol = 0.05;
  settings.paths = paths;
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  *exitCode = verdict(run::Console(MPI_COMM_WORLD), settings, m, "", true);
  const std::string out = ::testing::internal::GetCapturedStdout();
  return out + ::testing::internal::GetCapturedStderr();
}

// A result 2 % off that says 0.47 % (a face laid over another, before it was cut): within
// --tol, but its own estimate is 4x low and covers no patch: FAILED, naming why.
TEST(VerifyVerdict, FailsWhereTheFilesEstimateUnderstatesTheMeasuredError) {
  const Measures m = measureChannels(sampleWithEstimate(0.02, 0.0047, 0, 200), 3);
  int exitCode = -1;
  const std::string text = verdictWithEstimate(m, &exitCode);
  EXPECT_EQ(exitCode, 1) << text;
  EXPECT_NE(text.find("FAILED: the file's own error estimate understates"), std::string::npos)
      << text;
  EXPECT_FALSE(checkEstimate(m[0]).understated.empty());
  // The same error stated honestly passes.
  const Measures honest = measureChannels(sampleWithEstimate(0.02, 0.02, 0, 200), 3);
  EXPECT_EQ(verdictWithEstimate(honest, &exitCode).find("FAILED"), std::string::npos);
  EXPECT_EQ(exitCode, 0);
}

// Coverage far below 95 % fails even where the RMS figures agree: half the patches 3 sigma off,
// the other half exact (measured 0.0212 against an estimate of 0.012 per patch: 1.8x, within
// what the ratio alone allows).
TEST(VerifyVerdict, FailsWhereCoverageIsFarBelowItsNominalLevel) {
  std::vector<double> errors(200, 0.0);
  for (size_t k = 0; k < errors.size(); k += 2) errors[k] = 0.03;
  std::vector<Sampled> sample = sampleWithErrors(errors, 200);
  for (Sampled& s : sample)
    for (int c = 0; c < 3; ++c) s.radiosityStderr[c] = 0.012;
  const Measures m = measureChannels(sample, 3);
  EXPECT_NEAR(m[0].coverage, 0.5, 1e-12);
  int exitCode = -1;
  const std::string text = verdictWithEstimate(m, &exitCode);
  EXPECT_EQ(exitCode, 1) << text;
  EXPECT_NE(text.find("coverage 50.0 %"), std::string::npos) << text;
}

// A reference whose noise is as large as the error it measures cannot judge the estimate: said,
// with the --paths that would (noise / 2 at 4x the paths).
TEST(VerifyVerdict, SaysWhenTheReferenceNoiseIsTooLargeToJudgeTheEstimate) {
  const Measures m = measureChannels(sampleWithEstimate(0.02, 0.02, 0.02, 200), 3);
  int exitCode = -1;
  const std::string text = verdictWithEstimate(m, &exitCode, 16384);
  EXPECT_NE(text.find("the ratio estimate/measured is uncertain; --paths 65536"), std::string::npos)
      << text;
  // Quiet where the noise is small.
  const Measures quiet = measureChannels(sampleWithEstimate(0.02, 0.02, 0.002, 200), 3);
  EXPECT_EQ(verdictWithEstimate(quiet, &exitCode).find("uncertain"), std::string::npos);
}

// An estimate far above the error is on the safe side: a warning, not a failure.
TEST(VerifyVerdict, WarnsWhereTheEstimateIsFarAboveTheError) {
  const Measures m = measureChannels(sampleWithEstimate(0.005, 0.03, 0, 200), 3);
  int exitCode = -1;
  const std::string text = verdictWithEstimate(m, &exitCode);
  EXPECT_EQ(exitCode, 0) << text;
  EXPECT_NE(text.find("more than 2x the measured error"), std::string::npos) << text;
}

}  // namespace
}  // namespace radiosity::jobs
