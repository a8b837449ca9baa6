// `radiosity verify`: an independent check of a solved result. K reflecting patches are drawn
// at random (by a hash of seed and patch id, so the draw is the same on any number of ranks),
// their patch-averaged B is path-traced (verify/path_tracer.h: the mesh and ray casts only,
// never the result's form factors) and the result's B is compared with it, per channel.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/channels.h"
#include "core/error.h"
#include "core/mesh.h"
#include "io/store/collective.h"
#include "io/store/light_error.h"
#include "io/store/result.h"
#include "jobs/commands.h"
#include "jobs/console.h"
#include "jobs/output_paths.h"
#include "jobs/verify_pilot.h"
#include "trace/counter_rng.h"
#include "verify/path_tracer.h"

namespace radiosity::jobs {

namespace {

constexpr int kWorstShown = 5;
static_assert(VerifySettings{}.maxBounces == verify::kDefaultMaxBounces);

bool reflects(const Rgb& rho) { return rho[0] > 0 || rho[1] > 0 || rho[2] > 0; }

/// What the path tracer needs of a result, checked: a bad file is bad input (exit 3).
void checkResult(const Result& result, const std::string& path) {
  auto bad = [&](const std::string& what) { return InputError(path + ": " + what); };
  const Mesh& mesh = result.mesh;
  const size_t n = mesh.triangles.size();
  if (n == 0) throw bad("holds no patches");
  if (result.radiosity.size() != n || result.area.size() != n || mesh.reflectance.size() != n ||
      mesh.emission.size() != n)
    throw bad("holds radiosity, area, reflectance or emission for some patches only");
  if (const std::string problem = tracingProblem(mesh); !problem.empty()) throw bad(problem);
  for (size_t t = 0; t < n; ++t) {
    for (int c = 0; c < 3; ++c) {
      const double rho = mesh.reflectance[t][c], e = mesh.emission[t][c];
      if (!(rho >= 0 && rho <= 1))
        throw bad("patch " + std::to_string(t) + " has a reflectance outside [0, 1]");
      if (!(e >= 0) || !std::isfinite(e))
        throw bad("patch " + std::to_string(t) + " has an emission that is not finite and >= 0");
      if (!std::isfinite(result.radiosity[t][c]))
        throw bad("patch " + std::to_string(t) + " has a radiosity that is not a finite number");
    }
    if (!(result.area[t] > 0) || !std::isfinite(result.area[t]) ||
        !(mesh.area(static_cast<int64_t>(t)) > 0))
      throw bad("patch " + std::to_string(t) + " has no area");
  }
}

/// The sample: the `count` reflecting patches with the smallest hash of (seed, id), ties by
/// id, in ascending id order. The same on any number of ranks.
std::vector<int64_t> choosePatches(const Mesh& mesh, int64_t count, uint64_t seed) {
  std::vector<std::pair<uint64_t, int64_t>> keyed;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!reflects(mesh.reflectance[t])) continue;
    const auto bits = trace::philox4x32(
        {static_cast<uint32_t>(t), static_cast<uint32_t>(static_cast<uint64_t>(t) >> 32),
         0x76657269u /* "veri" */, 0},
        {static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32)});
    keyed.emplace_back((uint64_t{bits[0]} << 32) | bits[1], t);
  }
  const size_t k = std::min(keyed.size(), static_cast<size_t>(count));
  std::partial_sort(keyed.begin(), keyed.begin() + static_cast<ptrdiff_t>(k), keyed.end());
  std::vector<int64_t> chosen;
  for (size_t i = 0; i < k; ++i) chosen.push_back(keyed[i].second);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

/// Rank 0's progress on stderr (stdout keeps the report): at most every two seconds, and
/// nothing at all for a run shorter than that.
class Progress {
 public:
  Progress(const Console& console, int64_t patches, int64_t paths)
      : console_(console), patches_(patches), paths_(paths), start_(MPI_Wtime()), last_(start_) {}
  void operator()(int64_t done) {
    if (!console_.isRoot()) return;
    const double now = MPI_Wtime();
    if (now - last_ < 2.0 || done == patches_) return;
    last_ = now;
    const double elapsed = now - start_;
    // The ranks share the patches evenly (±1), so rank 0's pace is the job's.
    const double pathsPerSecond = static_cast<double>(done * paths_ * console_.ranks()) / elapsed;
    std::fprintf(stderr, "  verify: %lld/%lld patches on rank 0, %.3g paths/s, about %.0f s left\n",
                 static_cast<long long>(done), static_cast<long long>(patches_), pathsPerSecond,
                 elapsed * static_cast<double>(patches_ - done) / static_cast<double>(done));
    std::fflush(stderr);
  }

 private:
  const Console& console_;
  int64_t patches_, paths_;
  double start_, last_;
};

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
  double estimate = 0, coverage = 0;  ///< only with /patches/radiosity_stderr
};

double floorFor(double reference, double meanReference) {
  return std::max(reference, kLightErrorFloorShare * meanReference);
}

// In the measure of io/store/light_error.h over the sampled patches (on this rank: every rank holds
// the whole sample), relative to the reference: the result's error, the reference's noise and
// the result's own estimate; and the coverage of the error by both standard errors.
ChannelMeasures measure(const std::vector<Sampled>& sample, int c) {
  ChannelMeasures m;
  std::vector<double> area;
  std::vector<Rgb> rho, reference, gap, noise, estimate;
  int64_t covered = 0;
  for (const Sampled& s : sample) {
    if (!(s.rho[c] > 0)) continue;
    ++m.patches;
    area.push_back(s.area);
    rho.push_back({s.rho[c], 0, 0});
    reference.push_back({s.reference[c], 0, 0});
    gap.push_back({s.radiosity[c] - s.reference[c], 0, 0});
    noise.push_back({s.referenceStderr[c], 0, 0});
    estimate.push_back({s.radiosityStderr[c], 0, 0});
    const double sigma = std::hypot(s.radiosityStderr[c], s.referenceStderr[c]);
    if (std::abs(gap.back()[0]) <= 2 * sigma) ++covered;
  }
  if (m.patches == 0) return m;
  auto light = [&](const std::vector<Rgb>& error) {
    return relativeLightError(MPI_COMM_SELF, area, rho, reference, error)[0];
  };
  m.meanReference = reflectingMean(MPI_COMM_SELF, area, rho, reference)[0];
  m.measured = light(gap);
  m.noise = light(noise);
  m.corrected = std::sqrt(std::max(0.0, m.measured * m.measured - m.noise * m.noise));
  m.estimate = light(estimate);
  m.coverage = static_cast<double>(covered) / static_cast<double>(m.patches);
  return m;
}

std::string number(double x, const char* format = "%.4g") {
  char text[48];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

/// A table row: a label and one cell per channel ("-" where the channel has no patches).
std::string row(const std::string& label, const std::array<ChannelMeasures, 3>& channels,
                const std::function<std::string(const ChannelMeasures&)>& cell) {
  char text[64];
  std::snprintf(text, sizeof text, "  %-40s", label.c_str());
  std::string line = text;
  for (const ChannelMeasures& m : channels) {
    std::snprintf(text, sizeof text, "%12s", m.patches > 0 ? cell(m).c_str() : "-");
    line += text;
  }
  return line;
}

// The result's own estimate of its error at patch i: the sampling standard error, combined in
// quadrature with the estimated discretisation error where the file has one.
Rgb estimatedError(const Result& result, int64_t i) {
  Rgb error = result.radiosityStderr[i];
  if (!result.radiosityDiscretisation.empty())
    for (int c = 0; c < 3; ++c)
      error[c] = std::hypot(error[c], result.radiosityDiscretisation[i][c]);
  return error;
}

std::string csvOf(const std::vector<Sampled>& sample, bool hasStderr) {
  std::ostringstream csv;
  csv << "patch,channel,area,rho,emission,B,B_ref,B_ref_stderr,B_stderr\n";
  auto exact = [](double x) { return number(x, "%.17g"); };
  for (const Sampled& s : sample) {
    for (int c = 0; c < 3; ++c) {
      csv << s.patch << ',' << kChannelNames[c] << ',' << exact(s.area) << ',' << exact(s.rho[c])
          << ',' << exact(s.emission[c]) << ',' << exact(s.radiosity[c]) << ','
          << exact(s.reference[c]) << ',' << exact(s.referenceStderr[c]) << ','
          << (hasStderr ? exact(s.radiosityStderr[c]) : std::string()) << '\n';
    }
  }
  return csv.str();
}

}  // namespace

int runVerify(const VerifySettings& settings, const Console& console) {
  if (settings.paths < 2)
    throw Error(exit_code::kUsage,
                "verify: --paths must be at least 2 (the reference's error needs two paths)");
  const MPI_Comm comm = console.comm();
  runCollectively(console.comm(), [&] { checkOutputs({settings.csv}, {settings.input}); });

  Result result;
  runCollectively(console.comm(), [&] {
    result = readResult(settings.input);
    checkResult(result, settings.input);
  });
  normaliseForTracing(result.mesh);  // (the answer at any scale is the answer at scale 1)
  // Hidden patches (under objects, inside solids) were left out of the solve, B = E exactly:
  // nothing to check there, and no light reaches them for the paths either.
  for (size_t t = 0; t < result.hidden.size(); ++t)
    if (result.hidden[t]) result.mesh.reflectance[t] = Rgb{0, 0, 0};
  const Mesh& mesh = result.mesh;
  const bool hasStderr = !result.radiosityStderr.empty();
  const std::vector<int64_t> chosen = choosePatches(mesh, settings.patches, settings.seed);
  const int64_t reflecting = std::count_if(mesh.reflectance.begin(), mesh.reflectance.end(),
                                           [](const Rgb& rho) { return reflects(rho); });
  console.info("verify " + settings.input + ": " + std::to_string(mesh.triangleCount()) +
               " patches; " + std::to_string(chosen.size()) + " of the " +
               std::to_string(reflecting) + " reflecting ones sampled (seed " +
               std::to_string(settings.seed) + "), " + std::to_string(settings.paths) +
               " paths each");
  if (chosen.empty()) {
    console.info("verify: no patch reflects, so B = E exactly: nothing to check");
    return exit_code::kOk;
  }

  // This rank's share: sampled positions rank, rank + ranks, ...; the others stay 0, so that
  // a sum over the ranks assembles every reference exactly.
  std::vector<int64_t> mine;
  for (size_t k = static_cast<size_t>(console.rank()); k < chosen.size();
       k += static_cast<size_t>(console.ranks()))
    mine.push_back(chosen[k]);
  const size_t count = chosen.size();
  std::vector<double> references(6 * count, 0.0);
  int64_t rays = 0;
  const double start = MPI_Wtime();
  int64_t bounces = 0, capped = 0;
  runCollectively(console.comm(), [&] {
    verify::PathTracer tracer(mesh, settings.threads, settings.maxBounces);
    if (console.isRoot()) reportPilot(console, tracer, chosen, settings);
    Progress progress(console, static_cast<int64_t>(mine.size()), settings.paths);
    const auto traced = tracer.trace(mine, settings.paths, settings.seed, settings.threads,
                                     [&](int64_t done) { progress(done); });
    for (size_t m = 0; m < traced.size(); ++m) {
      const size_t k = static_cast<size_t>(console.rank()) + m * console.ranks();
      for (int c = 0; c < 3; ++c) {
        references[6 * k + c] = traced[m].radiosity[c];
        references[6 * k + 3 + c] = traced[m].standardError[c];
      }
      rays += traced[m].rays;
      bounces += traced[m].bounces;
      capped += traced[m].capped;
    }
  });
  constexpr size_t kChunk = size_t{1} << 28;  // MPI counts are int
  for (size_t first = 0; first < references.size(); first += kChunk)
    MPI_Allreduce(MPI_IN_PLACE, references.data() + first,
                  static_cast<int>(std::min(kChunk, references.size() - first)), MPI_DOUBLE,
                  MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &rays, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &bounces, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &capped, 1, MPI_INT64_T, MPI_SUM, comm);
  const double seconds = slowestRank(comm, MPI_Wtime() - start);
  console.info("  path tracing: " + number(static_cast<double>(rays), "%.3g") + " rays, " +
               number(seconds, "%.2f") + " s, " +
               number(static_cast<double>(count * settings.paths) / seconds, "%.3g") +
               " paths/s (" + std::to_string(console.ranks()) + " ranks x " +
               std::to_string(settings.threads) + " threads)");
  const double allPaths = static_cast<double>(count * settings.paths);
  const std::string cappedNote =
      capped == 0
          ? std::string()
          : std::to_string(capped) + " of " + number(allPaths, "%.0f") + " reference paths (" +
                number(100 * static_cast<double>(capped) / allPaths, "%.3g") +
                " %) were cut at --max-bounces " + std::to_string(settings.maxBounces);
  if (capped > 0)
    console.info("  cap reached: " + cappedNote + " (mean path " +
                 number(static_cast<double>(bounces) / allPaths, "%.3g") +
                 " bounces): the reference misses the light beyond the cap, so it is low "
                 "where they ran (reflectance near 1) and so is the error measured against it");

  std::vector<Sampled> sample;
  for (size_t k = 0; k < count; ++k) {
    const int64_t i = chosen[k];
    Sampled s{i,
              result.area[i],
              mesh.reflectance[i],
              mesh.emission[i],
              result.radiosity[i],
              hasStderr ? estimatedError(result, i) : Rgb{0, 0, 0},
              Rgb{},
              Rgb{}};
    for (int c = 0; c < 3; ++c) {
      s.reference[c] = references[6 * k + c];
      s.referenceStderr[c] = references[6 * k + 3 + c];
    }
    sample.push_back(s);
  }

  std::array<ChannelMeasures, 3> channels;
  for (int c = 0; c < 3; ++c) channels[c] = measure(sample, c);
  console.info(
      "relative error of B over the sampled patches that reflect in the channel: area-weighted "
      "RMS, each patch's error relative to max(B_ref, 1% of the mean B_ref)");
  char header[96];
  std::snprintf(header, sizeof header, "  %-40s%12s%12s%12s", "", kChannelNames[0],
                kChannelNames[1], kChannelNames[2]);
  console.info(header);
  console.info(
      row("patches", channels, [](const ChannelMeasures& m) { return std::to_string(m.patches); }));
  console.info(row("measured (result against reference)", channels,
                   [](const ChannelMeasures& m) { return number(m.measured); }));
  console.info(
      row("reference noise", channels, [](const ChannelMeasures& m) { return number(m.noise); }));
  console.info(row("measured, noise taken out", channels,
                   [](const ChannelMeasures& m) { return number(m.corrected); }));
  if (hasStderr) {
    console.info(row("file's own estimate of its error", channels,
                     [](const ChannelMeasures& m) { return number(m.estimate); }));
    console.info(
        row("estimate / measured (noise taken out)", channels, [](const ChannelMeasures& m) {
          return m.corrected > 0 ? number(m.estimate / m.corrected, "%.3g") : std::string("n/a");
        }));
    console.info(row("coverage: |B - B_ref| <= 2 sigma", channels, [](const ChannelMeasures& m) {
      return number(100 * m.coverage, "%.1f") + " %";
    }));
  } else {
    console.info("  (the file has no /patches/radiosity_stderr: no estimate to compare)");
  }

  // The worst patches: by their largest relative error over the channels they reflect in.
  struct Worst {
    double relative;
    size_t k;
    int channel;
  };
  std::vector<Worst> worst;
  for (size_t k = 0; k < count; ++k) {
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
  console.info("worst patches (relative error in their worst channel):");
  for (const Worst& w : worst) {
    const Sampled& s = sample[w.k];
    const int c = w.channel;
    console.info("  patch " + std::to_string(s.patch) + " " + kChannelNames[c] + ": B " +
                 number(s.radiosity[c]) + ", B_ref " + number(s.reference[c]) + " +- " +
                 number(s.referenceStderr[c], "%.2g") + ", relative error " +
                 number(w.relative, "%+.3g"));
  }

  if (!settings.csv.empty()) {
    runCollectively(console.comm(), [&] {
      if (console.isRoot()) writeTextFilesAtomically({{settings.csv, csvOf(sample, hasStderr)}});
    });
    console.info("wrote " + settings.csv);
  }

  // The verdict, on the error with the reference's own noise taken out.
  std::string above, noisy;
  double largestError = 0;
  for (int c = 0; c < 3; ++c) {
    if (channels[c].patches == 0) continue;
    largestError = std::max(largestError, channels[c].corrected);
    if (!(channels[c].corrected <= settings.tol))
      above += std::string(above.empty() ? "" : ", ") + kChannelNames[c];
    // Noise above half the tolerance makes a pass (or a near miss) uncertain; a clear miss
    // stays one.
    if (channels[c].noise > 0.5 * settings.tol &&
        channels[c].corrected <= settings.tol + 2 * channels[c].noise)
      noisy += std::string(noisy.empty() ? "" : ", ") + kChannelNames[c];
  }
  if (!noisy.empty())
    console.warn("verify: the reference noise in " + noisy + " is above half of --tol " +
                 number(settings.tol) + ": the verdict is uncertain, give more --paths");
  const std::string against =
      capped > 0 ? "; against a reference cut short: " + cappedNote : std::string();
  if (!above.empty()) {
    console.info("verify: FAILED: the measured error (noise taken out) is above --tol " +
                 number(settings.tol) + " in " + above + " (largest " + number(largestError) + ")" +
                 against);
    return exit_code::kFailure;
  }
  console.info("verify: passed: the measured error (noise taken out) is at most --tol " +
               number(settings.tol) + " in every channel (largest " + number(largestError) + ")" +
               against);
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
