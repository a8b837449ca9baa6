#include "jobs/verify_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>

#include "core/error.h"
#include "measure/light_error.h"

namespace radiosity::jobs {

namespace {

constexpr int kWorstShown = 5;

double floorFor(double reference, double meanReference) {
  return std::max(reference, kLightErrorFloorShare * meanReference);
}

// ChannelMeasures' interval: the noise-taken-out error over resamples of the patches. `error`
// and `noise` are each patch's squared relative terms, `area` its weight (the floor kept at the
// whole sample's: it moves little between resamples).
void sampleInterval(const std::vector<double>& area, const std::vector<double>& error,
                    const std::vector<double>& noise, ChannelMeasures& m) {
  std::mt19937_64 generator(0x5eed);
  std::uniform_int_distribution<size_t> pick(0, area.size() - 1);
  std::vector<double> corrected(kSampleResamples);
  for (double& value : corrected) {
    double weight = 0, errors = 0, noises = 0;
    for (size_t drawn = 0; drawn < area.size(); ++drawn) {
      const size_t k = pick(generator);
      weight += area[k];
      errors += area[k] * error[k];
      noises += area[k] * noise[k];
    }
    value = weight > 0 ? std::sqrt(std::max(0.0, (errors - noises) / weight)) : 0.0;
  }
  std::sort(corrected.begin(), corrected.end());
  m.correctedLow = corrected[kSampleResamples / 20];
  m.correctedHigh = corrected[kSampleResamples - 1 - kSampleResamples / 20];
}

// A share of the measure's floor below which an error is nothing (coverage).
constexpr double kNegligibleShare = 1e-6;

// In the measure of measure/light_error.h over the sampled patches (on this rank: every rank holds
// the whole sample), relative to the reference: the result's error, the reference's noise and
// the result's own estimate; and the coverage of the error by both standard errors.
ChannelMeasures measure(const std::vector<Sampled>& sample, int c) {
  ChannelMeasures m;
  std::vector<double> area;
  std::vector<Rgb> rho, reference, gap, noise, estimate;
  for (const Sampled& s : sample) {
    if (!(s.rho[c] > 0)) continue;
    ++m.patches;
    area.push_back(s.area);
    rho.push_back({s.rho[c], 0, 0});
    reference.push_back({s.reference[c], 0, 0});
    gap.push_back({s.radiosity[c] - s.reference[c], 0, 0});
    noise.push_back({s.referenceStderr[c], 0, 0});
    estimate.push_back({s.radiosityStderr[c], 0, 0});
  }
  if (m.patches == 0) return m;
  auto light = [&](const std::vector<Rgb>& error) {
    return relativeLightError(MPI_COMM_SELF, area, rho, reference, error)[0];
  };
  m.meanReference = reflectingMean(MPI_COMM_SELF, area, rho, reference)[0];
  // Coverage over the patches some light reaches (the measure's; none where B and B_ref are both
  // 0). An error below a millionth of the measure's floor is covered whatever the σ: it is light
  // the measure cannot see (the 1e-13 a path tracer finds on ground 500 m from a window, where
  // the run's 0 has no σ), far below any error a run quotes.
  int64_t judged = 0, covered = 0;
  for (size_t k = 0; k < area.size(); ++k) {
    if (reference[k][0] == 0 && gap[k][0] == 0) continue;
    ++judged;
    const double sigma = std::hypot(estimate[k][0], noise[k][0]);
    const double negligible = kNegligibleShare * kLightErrorFloorShare * m.meanReference;
    if (std::abs(gap[k][0]) <= std::max(2 * sigma, negligible)) ++covered;
  }
  m.measured = light(gap);
  m.noise = light(noise);
  m.corrected = std::sqrt(std::max(0.0, m.measured * m.measured - m.noise * m.noise));
  m.estimate = light(estimate);
  m.coverage = judged > 0 ? static_cast<double>(covered) / static_cast<double>(judged) : 1.0;
  std::vector<double> judgedArea, squaredError, squaredNoise;
  for (size_t k = 0; k < area.size(); ++k) {
    if (reference[k][0] == 0 && gap[k][0] == 0) continue;  // as the measure: no light there
    judgedArea.push_back(area[k]);
    const double floor = kLightErrorFloorShare * m.meanReference;
    squaredError.push_back(
        std::pow(relativeToFloor(std::abs(gap[k][0]), reference[k][0], floor), 2));
    squaredNoise.push_back(std::pow(relativeToFloor(noise[k][0], reference[k][0], floor), 2));
  }
  if (!judgedArea.empty()) sampleInterval(judgedArea, squaredError, squaredNoise, m);
  return m;
}

/// A table row: a label and one cell per channel ("-" where the channel has no patches).
std::string row(const std::string& label, const Measures& channels,
                const std::function<std::string(const ChannelMeasures&)>& cell) {
  char text[64];
  std::snprintf(text, sizeof text, "  %-40s", label.c_str());
  std::string line = text;
  for (int c = 0; c < channels.count; ++c) {
    const ChannelMeasures& m = channels[c];
    std::snprintf(text, sizeof text, "%12s", m.patches > 0 ? cell(m).c_str() : "-");
    line += text;
  }
  return line;
}

}  // namespace

std::string number(double x, const char* format) {
  char text[48];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

Measures measureChannels(const std::vector<Sampled>& sample, int count) {
  Measures channels;
  channels.count = count;
  for (int c = 0; c < count; ++c) channels[c] = measure(sample, c);
  return channels;
}

void printMeasures(const run::Console& console, const Measures& channels, bool hasStderr) {
  console.result(
      "relative error of B over the sampled patches that reflect in the channel: area-weighted "
      "RMS, each patch's error relative to max(B_ref, 1% of the mean B_ref)");
  char text[64];
  std::snprintf(text, sizeof text, "  %-40s", "");
  std::string header = text;
  for (int c = 0; c < channels.count; ++c) {
    const std::string name = channels.name(c);
    header += std::string(name.size() < 12 ? 12 - name.size() : 0, ' ') + name;
  }
  console.result(header);
  console.result(
      row("patches", channels, [](const ChannelMeasures& m) { return std::to_string(m.patches); }));
  console.result(row("measured (result against reference)", channels,
                     [](const ChannelMeasures& m) { return number(m.measured); }));
  console.result(
      row("reference noise", channels, [](const ChannelMeasures& m) { return number(m.noise); }));
  console.result(row("measured, noise taken out", channels,
                     [](const ChannelMeasures& m) { return number(m.corrected); }));
  // (how far the patches drawn leave that figure uncertain: ChannelMeasures)
  console.result(row("  5 % quantile, the patches resampled", channels,
                     [](const ChannelMeasures& m) { return number(m.correctedLow); }));
  console.result(row("  95 % quantile, the patches resampled", channels,
                     [](const ChannelMeasures& m) { return number(m.correctedHigh); }));
  if (!hasStderr) {
    console.result("  (the file has no /patches/radiosity_stderr: no estimate to compare)");
    return;
  }
  console.result(row("file's own estimate of its error", channels,
                     [](const ChannelMeasures& m) { return number(m.estimate); }));
  console.result(
      row("estimate / measured (noise taken out)", channels, [](const ChannelMeasures& m) {
        return m.corrected > 0 ? number(m.estimate / m.corrected, "%.3g") : std::string("n/a");
      }));
  console.result(row("coverage: |B - B_ref| <= 2 sigma", channels, [](const ChannelMeasures& m) {
    return number(100 * m.coverage, "%.1f") + " %";
  }));
}

void printWorstPatches(const run::Console& console, const std::vector<Sampled>& sample,
                       const Measures& channels) {
  // By their largest relative error over the channels they reflect in.
  struct Worst {
    double relative;
    size_t k;
    int channel;
  };
  std::vector<Worst> worst;
  for (size_t k = 0; k < sample.size(); ++k) {
    const Sampled& s = sample[k];
    Worst w{0, k, -1};
    for (int c = 0; c < 3; ++c) {
      if (channels[c].patches == 0 || !(s.rho[c] > 0)) continue;
      const double scale = floorFor(s.reference[c], channels[c].meanReference);
      const double relative = scale > 0 ? (s.radiosity[c] - s.reference[c]) / scale : 0;
      if (w.channel < 0 || std::abs(relative) > std::abs(w.relative)) w = {relative, k, c};
    }
    if (w.channel >= 0) worst.push_back(w);
  }
  std::stable_sort(worst.begin(), worst.end(), [](const Worst& a, const Worst& b) {
    return std::abs(a.relative) > std::abs(b.relative);
  });
  if (worst.size() > kWorstShown) worst.resize(kWorstShown);
  console.result("worst patches (relative error in their worst channel):");
  for (const Worst& w : worst) {
    const Sampled& s = sample[w.k];
    const int c = w.channel;
    console.result("  patch " + std::to_string(s.patch) + " " + channels.name(c) + ": B " +
                   number(s.radiosity[c]) + ", B_ref " + number(s.reference[c]) + " +- " +
                   number(s.referenceStderr[c], "%.2g") + ", relative error " +
                   number(w.relative, "%+.3g"));
  }
}

std::string csvOf(const std::vector<Sampled>& sample, bool hasStderr, int count) {
  std::ostringstream csv;
  csv << "patch,channel,area,rho,emission,B,B_ref,B_ref_stderr,B_stderr\n";
  auto exact = [](double x) { return number(x, "%.17g"); };
  for (const Sampled& s : sample) {
    for (int c = 0; c < count; ++c) {
      csv << s.patch << ',' << channelName(c, count) << ',' << exact(s.area) << ','
          << exact(s.rho[c]) << ',' << exact(s.emission[c]) << ',' << exact(s.radiosity[c]) << ','
          << exact(s.reference[c]) << ',' << exact(s.referenceStderr[c]) << ','
          << (hasStderr ? exact(s.radiosityStderr[c]) : std::string()) << '\n';
    }
  }
  return csv.str();
}

namespace {

// --paths that bring the reference's noise to `wanted` (noise falls as 1/sqrt(paths)), as a
// power of two.
int64_t pathsFor(int64_t paths, double noise, double wanted) {
  const double needed = static_cast<double>(paths) * (noise / wanted) * (noise / wanted);
  int64_t shown = paths;
  while (static_cast<double>(shown) < needed && shown < (int64_t{1} << 40)) shown *= 2;
  return shown;
}

}  // namespace

EstimateCheck checkEstimate(const ChannelMeasures& m) {
  EstimateCheck check;
  if (m.patches == 0) return check;
  // Understated: even the 5 % quantile of the measured error over the patches drawn is above
  // kEstimateSlack times the estimate (judged where the reference's noise, taken out of the
  // measure, is below half of it: else the noise's own noise decides), or the errors fall
  // outside 2 sigma on most patches (a test the noise makes only easier to pass).
  if (m.correctedLow > kEstimateSlack * m.estimate && m.noise <= 0.5 * m.corrected)
    check.understated = "measured " + number(m.corrected, "%.3g") + " (at least " +
                        number(m.correctedLow, "%.3g") + ") against an estimate of " +
                        number(m.estimate, "%.3g");
  else if (m.coverage < kLeastCoverage)
    check.understated = "coverage " + number(100 * m.coverage, "%.1f") + " % where about 95 % is " +
                        "expected (at least " + number(100 * kLeastCoverage, "%.0f") + " %)";
  // Overstated: the estimate above kEstimateSlack times even the 95 % quantile; safe, but
  // the figure says less than the result is worth.
  if (m.estimate > kEstimateSlack * m.correctedHigh && m.correctedHigh > m.noise)
    check.overstated = "estimate " + number(m.estimate, "%.3g") + " against a measured " +
                       number(m.corrected, "%.3g");
  return check;
}

int verdict(const run::Console& console, const VerifySettings& settings, const Measures& channels,
            const std::string& cappedNote, bool hasStderr) {
  std::string above, noisy, undecided, understated, overstated, unjudged;
  double largestError = 0, noisiest = 0, judgedAgainst = 0;
  auto add = [](std::string& list, const std::string& item) {
    list += (list.empty() ? "" : ", ") + item;
  };
  for (int c = 0; c < 3; ++c) {
    const ChannelMeasures& m = channels[c];
    if (m.patches == 0) continue;
    largestError = std::max(largestError, m.corrected);
    if (!(m.corrected <= settings.tol)) add(above, channels.name(c));
    // Noise above half the tolerance makes a pass (or a near miss) uncertain; a clear miss
    // stays one. Else, --tol between the quantiles over the patches resampled does.
    if (m.noise > 0.5 * settings.tol && m.corrected <= settings.tol + 2 * m.noise) {
      add(noisy, channels.name(c));
    } else if (m.correctedLow <= settings.tol && settings.tol < m.correctedHigh) {
      add(undecided, std::string(channels.name(c)) + " " + number(m.correctedLow, "%.3g") + " to " +
                         number(m.correctedHigh, "%.3g"));
    }
    if (!hasStderr) continue;
    const EstimateCheck check = checkEstimate(m);
    if (!check.understated.empty())
      add(understated, std::string(channels.name(c)) + ": " + check.understated);
    if (!check.overstated.empty())
      add(overstated, std::string(channels.name(c)) + ": " + check.overstated);
    // The noise taken out of a measure it is as large as leaves their ratio uncertain (where
    // the error is large enough to matter: an exact answer's 1e-9 needs no judging).
    const double judged = std::max(m.estimate, m.corrected);
    if (m.noise > 0.5 * judged && judged >= 0.1 * settings.tol) {
      add(unjudged, channels.name(c));
      if (m.noise / judged > noisiest / std::max(judgedAgainst, 1e-300))
        noisiest = m.noise, judgedAgainst = judged;
    }
  }
  if (!undecided.empty())
    console.warn("verify: --tol " + number(settings.tol) +
                 " lies between the 5 % and 95 % quantiles of the measured error over resamples of "
                 "the patches drawn (" +
                 undecided + "): the verdict is uncertain, give more --patches");
  if (!noisy.empty())
    console.warn("verify: the reference noise in " + noisy + " is above half of --tol " +
                 number(settings.tol) + ": the verdict is uncertain, give more --paths");
  if (!unjudged.empty())
    console.warn("verify: the reference noise in " + unjudged +
                 " is above half of the error it measures (" + number(noisiest, "%.3g") +
                 " against " + number(judgedAgainst, "%.3g") +
                 "): the ratio estimate/measured is uncertain; --paths " +
                 std::to_string(pathsFor(settings.paths, noisiest, 0.5 * judgedAgainst)) +
                 " would bring the noise to half of it");
  if (!overstated.empty())
    console.warn("verify: the file's own error estimate is more than " +
                 number(kEstimateSlack, "%g") + "x the measured error (" + overstated +
                 "): on the safe side, but the result is better than it says");
  const std::string against =
      cappedNote.empty() ? std::string() : "; against a reference cut short: " + cappedNote;
  if (!above.empty()) {
    console.result("verify: FAILED: the measured error (noise taken out) is above --tol " +
                   number(settings.tol) + " in " + above + " (largest " + number(largestError) +
                   ")" + against);
    return exit_code::kFailure;
  }
  // Against a reference cut short (low by what its paths missed) the estimate cannot be judged.
  if (!understated.empty() && !cappedNote.empty()) {
    console.warn(
        "verify: the file's own error estimate is below the error measured against a "
        "reference cut short (" +
        understated + "): not judged, as the reference is low");
    understated.clear();
  }
  if (!understated.empty()) {
    console.result(
        "verify: FAILED: the file's own error estimate understates the measured error (" +
        understated + "): its error figures cannot be trusted" + against);
    return exit_code::kFailure;
  }
  console.result(
      "verify: passed: the measured error (noise taken out) is at most --tol " +
      number(settings.tol) + " in every channel (largest " + number(largestError) + ")" +
      (hasStderr && cappedNote.empty() ? ", and the file's own estimate covers it" : "") + against);
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
