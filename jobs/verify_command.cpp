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
#include "io/store/result.h"
#include "jobs/commands.h"
#include "jobs/json_summaries.h"
#include "jobs/verify_pilot.h"
#include "jobs/verify_report.h"
#include "parallel/collective.h"
#include "run/console.h"
#include "run/output_paths.h"
#include "run/stage_reports.h"
#include "trace/random_streams.h"
#include "verify/path_tracer.h"

namespace radiosity::jobs {

namespace {

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
/// id, in ascending id order; those the result has lit (B > 0) first, so that a room on a
/// ground of 10^6 m² is judged on its own patches, not on the unlit ground (whose B = 0 the
/// measure leaves out where the reference agrees). The same on any number of ranks.
std::vector<int64_t> choosePatches(const Mesh& mesh, const std::vector<Rgb>& radiosity,
                                   int64_t count, uint64_t seed) {
  trace::KeyedIds keyed;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!reflects(mesh.reflectance[t])) continue;
    const uint64_t hash = trace::streamHash(seed, static_cast<uint64_t>(t), trace::kVerifySample);
    const Rgb& b = radiosity[t];
    keyed.emplace_back(trace::sampleKey(hash, b[0] > 0 || b[1] > 0 || b[2] > 0), t);
  }
  return trace::idsOf(trace::smallestKeys(std::move(keyed), count));
}

// The result, checked, in the frame it is traced in, its hidden patches dark: hidden patches
// (under objects, inside solids) were left out of the solve, B = E exactly: nothing to check
// there, and no light reaches them for the paths either.
Result readVerifiable(const std::string& path, const run::Console& console) {
  Result result;
  runCollectively(console.comm(), [&] {
    result = readResult(path);
    checkResult(result, path);
  });
  normaliseForTracing(result.mesh);  // (the answer at any scale is the answer at scale 1)
  for (size_t t = 0; t < result.hidden.size(); ++t)
    if (result.hidden[t]) result.mesh.reflectance[t] = Rgb{0, 0, 0};
  return result;
}

/// The reference of every chosen patch, summed over the ranks, and what tracing it took.
struct References {
  std::vector<double> values;  ///< per chosen patch: B, then its standard error, per channel
  int64_t rays = 0, bounces = 0, capped = 0;
  double seconds = 0;  ///< the slowest rank's
  double radiosity(size_t k, int c) const { return values[6 * k + c]; }
  double standardError(size_t k, int c) const { return values[6 * k + 3 + c]; }
};

// Each rank traces the sampled positions rank, rank + ranks, ...; the others stay 0, so that a
// sum over the ranks assembles every reference exactly. Collective.
References traceReferences(const run::Console& console, const VerifySettings& settings,
                           const Mesh& mesh, const std::vector<int64_t>& chosen) {
  const MPI_Comm comm = console.comm();
  std::vector<int64_t> mine;
  for (size_t k = static_cast<size_t>(console.rank()); k < chosen.size();
       k += static_cast<size_t>(console.ranks()))
    mine.push_back(chosen[k]);
  References references;
  references.values.assign(6 * chosen.size(), 0.0);
  const double start = MPI_Wtime();
  runCollectively(comm, [&] {
    verify::PathTracer tracer(mesh, settings.threads, settings.maxBounces);
    if (console.isRoot()) reportPilot(console, tracer, chosen, settings);
    run::ProgressReporter progress(console, static_cast<int64_t>(mine.size()), settings.paths,
                                   "paths", "verify");
    const auto traced = tracer.trace(mine, settings.paths, settings.seed, settings.threads,
                                     [&](int64_t done) { progress(done); });
    for (size_t m = 0; m < traced.size(); ++m) {
      const size_t k = static_cast<size_t>(console.rank()) + m * console.ranks();
      for (int c = 0; c < 3; ++c) {
        references.values[6 * k + c] = traced[m].radiosity[c];
        references.values[6 * k + 3 + c] = traced[m].standardError[c];
      }
      references.rays += traced[m].rays;
      references.bounces += traced[m].bounces;
      references.capped += traced[m].capped;
    }
  });
  std::vector<double>& values = references.values;
  constexpr size_t kChunk = size_t{1} << 28;  // MPI counts are int
  for (size_t first = 0; first < values.size(); first += kChunk)
    MPI_Allreduce(MPI_IN_PLACE, values.data() + first,
                  static_cast<int>(std::min(kChunk, values.size() - first)), MPI_DOUBLE, MPI_SUM,
                  comm);
  MPI_Allreduce(MPI_IN_PLACE, &references.rays, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &references.bounces, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &references.capped, 1, MPI_INT64_T, MPI_SUM, comm);
  references.seconds = run::slowestRank(comm, MPI_Wtime() - start);
  return references;
}

// The tracing's pace, and how many paths --max-bounces cut; returns the note on the cut paths
// ("" when none was cut) for the verdict.
std::string reportTracing(const run::Console& console, const VerifySettings& settings,
                          const References& references, size_t count) {
  const double allPaths = static_cast<double>(count * settings.paths);
  console.info("  path tracing: " + number(static_cast<double>(references.rays), "%.3g") +
               " rays, " + number(references.seconds, "%.2f") + " s, " +
               number(allPaths / references.seconds, "%.3g") + " paths/s (" +
               std::to_string(console.ranks()) + " ranks x " + std::to_string(settings.threads) +
               " threads)");
  if (references.capped == 0) return std::string();
  const std::string cappedNote =
      std::to_string(references.capped) + " of " + number(allPaths, "%.0f") + " reference paths (" +
      number(100 * static_cast<double>(references.capped) / allPaths, "%.3g") +
      " %) were cut at --max-bounces " + std::to_string(settings.maxBounces);
  console.info("  cap reached: " + cappedNote + " (mean path " +
               number(static_cast<double>(references.bounces) / allPaths, "%.3g") +
               " bounces): the reference misses the light beyond the cap, so it is low "
               "where they ran (reflectance near 1) and so is the error measured against it");
  return cappedNote;
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

// The chosen patches' values in the result, beside their references.
std::vector<Sampled> sampleOf(const Result& result, const std::vector<int64_t>& chosen,
                              const References& references) {
  const bool hasStderr = !result.radiosityStderr.empty();
  std::vector<Sampled> sample;
  for (size_t k = 0; k < chosen.size(); ++k) {
    const int64_t i = chosen[k];
    Sampled s{i,
              result.area[i],
              result.mesh.reflectance[i],
              result.mesh.emission[i],
              result.radiosity[i],
              hasStderr ? estimatedError(result, i) : Rgb{0, 0, 0},
              Rgb{},
              Rgb{}};
    for (int c = 0; c < 3; ++c) {
      s.reference[c] = references.radiosity(k, c);
      s.referenceStderr[c] = references.standardError(k, c);
    }
    sample.push_back(s);
  }
  return sample;
}

}  // namespace

int runVerify(const VerifySettings& settings, const run::Console& console) {
  runCollectively(console.comm(), [&] { run::checkOutputs({settings.csv}, {settings.input}); });
  const Result result = readVerifiable(settings.input, console);
  const Mesh& mesh = result.mesh;
  const bool hasStderr = !result.radiosityStderr.empty();
  const std::vector<int64_t> chosen =
      choosePatches(mesh, result.radiosity, settings.patches, settings.seed);
  const int64_t reflecting = std::count_if(mesh.reflectance.begin(), mesh.reflectance.end(),
                                           [](const Rgb& rho) { return reflects(rho); });
  console.info("verify " + settings.input + ": " + std::to_string(mesh.triangleCount()) +
               " patches; " + std::to_string(chosen.size()) + " of the " +
               std::to_string(reflecting) + " reflecting ones sampled, lit ones first (seed " +
               std::to_string(settings.seed) + "), " + std::to_string(settings.paths) +
               " paths each");
  if (chosen.empty()) {
    console.info("verify: no patch reflects, so B = E exactly: nothing to check");
    if (console.isJson())
      console.json(verifyJson(settings, mesh.triangleCount(), reflecting, 0, Measures{}, hasStderr,
                              "", exit_code::kOk));
    return exit_code::kOk;
  }

  const References references = traceReferences(console, settings, mesh, chosen);
  const std::string cappedNote = reportTracing(console, settings, references, chosen.size());
  const std::vector<Sampled> sample = sampleOf(result, chosen, references);
  const Measures channels = measureChannels(sample, result.attributes.channels == 1 ? 1 : 3);
  printMeasures(console, channels, hasStderr);
  printWorstPatches(console, sample, channels);
  if (!settings.csv.empty()) {
    runCollectively(console.comm(), [&] {
      if (console.isRoot())
        writeTextFilesAtomically({{settings.csv, csvOf(sample, hasStderr, channels.count)}});
    });
    console.info("wrote " + settings.csv);
  }
  // The verdict, on the error with the reference's own noise taken out.
  const int code = verdict(console, settings, channels, cappedNote, hasStderr);
  if (console.isJson())
    console.json(verifyJson(settings, mesh.triangleCount(), reflecting,
                            static_cast<int64_t>(chosen.size()), channels, hasStderr, cappedNote,
                            code));
  return code;
}

}  // namespace radiosity::jobs
