// `radiosity study`: what accuracy each setting buys and at what cost. The scene is loaded once,
// each mesh refined and its BVH built once, and for each estimator the rays are added to the
// same rows setting after setting (the sampling is extensible), so a sweep over rays costs what
// its largest setting costs. Every setting's B and H are compared with the scene's exact answer
// (jobs/study/exact_answers.h) or with a reference result file. The rows and the tracer are built
// by the same pieces as the solve pipeline's (jobs/pipeline_parts.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "formfactor/formfactor.h"
#include "io/core/atomic_file.h"
#include "io/core/channels.h"
#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/collective.h"
#include "io/store/light_error.h"
#include "io/store/result.h"
#include "jobs/commands.h"
#include "jobs/console.h"
#include "jobs/error_calibration.h"
#include "jobs/memory_check.h"
#include "jobs/output_paths.h"
#include "jobs/pipeline_parts.h"
#include "jobs/study/exact_answers.h"
#include "jobs/study/svg_plot.h"
#include "partition/partition.h"
#include "solve/solve.h"

namespace radiosity::jobs {

namespace {

// The answer each setting is compared with, for this rank's rows.
struct Reference {
  std::vector<Rgb> radiosity, irradiance;
  std::string how;
};

Reference referenceFor(const StudySettings& settings, const Mesh& patches,
                       partition::PatchRange owned) {
  Reference reference;
  std::vector<Rgb> allB, allH;
  if (!settings.reference.empty()) {
    Result result = readResult(settings.reference);
    if (result.mesh.triangles != patches.triangles) {
      throw InputError(settings.reference + ": its mesh (" +
                       std::to_string(result.mesh.triangleCount()) +
                       " patches) is not this study's (" + std::to_string(patches.triangleCount()) +
                       " patches): solve the same scene with the same --max-area");
    }
    allB = std::move(result.radiosity);
    allH = std::move(result.irradiance);
    reference.how = "reference " + settings.reference;
  } else {
    std::optional<ExactAnswer> exact = exactAnswer(settings.scene, patches);
    if (!exact) {
      throw InputError(settings.scene +
                       ": no exact answer is known for this scene; give --reference FILE.h5, a "
                       "high-effort solve of the same scene and --max-area");
    }
    allB = std::move(exact->radiosity);
    allH = std::move(exact->irradiance);
    reference.how = exact->how;
  }
  reference.radiosity.assign(allB.begin() + owned.begin, allB.begin() + owned.end);
  reference.irradiance.assign(allH.begin() + owned.begin, allH.begin() + owned.end);
  return reference;
}

// Errors per channel in the measure of io/store/light_error.h (RMS over the reflecting patches of
// each patch's error relative to its reference value, floored at 1 % of the mean), the largest
// such relative error, and the share of reflecting patches whose error is within twice the
// estimated standard error (when there is one).
struct ChannelErrors {
  Rgb rms{0, 0, 0}, largest{0, 0, 0}, covered{0, 0, 0};
};

ChannelErrors compare(MPI_Comm comm, const std::vector<Rgb>& value, const std::vector<Rgb>& exact,
                      const std::vector<double>& area, const std::vector<Rgb>& reflectance,
                      const std::vector<Rgb>& standardError) {
  std::vector<Rgb> gap(value.size());
  for (size_t i = 0; i < value.size(); ++i)
    for (int c = 0; c < 3; ++c) gap[i][c] = value[i][c] - exact[i][c];
  ChannelErrors errors;
  errors.rms = relativeLightError(comm, area, reflectance, exact, gap);
  const std::array<double, 3> mean = reflectingMean(comm, area, reflectance, exact);
  double counts[6] = {0, 0, 0, 0, 0, 0};  // covered, reflecting
  for (size_t i = 0; i < value.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0) continue;
      errors.largest[c] = std::max(errors.largest[c], relativeToFloor(std::abs(gap[i][c]), exact[i][c],
                                                                      kLightErrorFloorShare * mean[c]));
      counts[3 + c] += 1;
      if (!standardError.empty() && std::abs(gap[i][c]) <= 2 * standardError[i][c]) counts[c] += 1;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, errors.largest.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, counts, 6, MPI_DOUBLE, MPI_SUM, comm);
  for (int c = 0; c < 3; ++c) errors.covered[c] = counts[3 + c] > 0 ? counts[c] / counts[3 + c] : 0;
  return errors;
}

double worst(const Rgb& v) { return std::max({v[0], v[1], v[2]}); }

std::string csvHeader() {
  std::string header =
      "scene,max_area,patches,estimator,rays,solver,rtol,seconds_mesh,seconds_formfactors,"
      "seconds_solve,seconds_total,iterations,residual,error_bound";
  for (const char* what : {"B_error", "B_max", "H_error", "H_max", "B_estimate", "H_estimate",
                           "B_coverage"})
    for (const char* channel : kChannelNames)
      header += std::string(",") + what + "_" + channel;
  return header + "\n";
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

// One curve per estimator (and per tolerance or mesh when they are swept too).
struct Curves {
  std::map<std::string, PlotSeries> byLabel;
  void add(const std::string& label, double x, double y, bool dashed = false) {
    PlotSeries& series = byLabel[label];
    series.label = label;
    series.dashed = dashed;
    series.x.push_back(x);
    series.y.push_back(y);
  }
  std::vector<PlotSeries> list() const {
    std::vector<PlotSeries> all;
    for (const auto& [label, series] : byLabel) all.push_back(series);
    return all;
  }
};

}  // namespace

int runStudy(const StudySettings& requested, const Console& console) {
  StudySettings settings = requested;
  std::sort(settings.rays.begin(), settings.rays.end());
  settings.rays.erase(std::unique(settings.rays.begin(), settings.rays.end()), settings.rays.end());
  const MPI_Comm comm = console.comm();
  runCollectively(console.comm(), [&] {
    checkOutputs({settings.output, settings.plot}, {settings.scene, settings.reference});
  });

  Mesh scene;
  runCollectively(console.comm(), [&] { scene = loadScene(settings.scene); });
  std::vector<double> maxAreas = settings.maxAreas;
  if (maxAreas.empty()) maxAreas.push_back(scene.totalArea() / kAutoPatchDivisor);

  std::ostringstream csv;
  csv << csvHeader();
  Curves errorAgainstTime;
  std::vector<PlotSeries> solverCurves, solverTimeCurves;
  // (against the iterations per channel solved, like the residuals)
  PlotSeries solverError{"error of B where it stopped (each --rtol)", {}, {}, true};
  PlotSeries solverErrorByTime = solverError;
  for (double maxArea : maxAreas) {
    checkMeshFits(comm, scene.totalArea(), scene.triangleCount(), 0, maxArea,
                  "--max-area " + number(maxArea));
    double start = MPI_Wtime();
    Mesh patches;
    runCollectively(console.comm(),
                  [&] { patches = partition::orderAlongCurve(partition::refine(scene, maxArea)); });
    const double meshSeconds = slowestRank(comm, MPI_Wtime() - start);
    const int64_t patchCount = patches.triangleCount();
    const partition::PatchRange owned = ownedRows(console, patchCount);
    Reference reference;
    runCollectively(console.comm(), [&] { reference = referenceFor(settings, patches, owned); });
    console.info("study: " + std::to_string(patchCount) + " patches (max area " + number(maxArea) +
                 "), compared with the " + reference.how);
    normaliseForTracing(patches);  // (the answer at any scale is the answer at scale 1)
    const OwnedPatches local = ownedPatches(patches, owned);
    const std::vector<double>& area = local.area;
    const std::vector<Rgb>& reflectance = local.reflectance;
    const std::vector<Rgb>& emission = local.emission;
    const std::unique_ptr<formfactor::SceneTracer> tracer =
        buildTracer(console, patches, settings.threads);

    for (formfactor::Estimator estimator : settings.estimators) {
      formfactor::Options sampling;
      sampling.seed = settings.seed;
      sampling.threads = settings.threads;
      sampling.estimator = estimator;
      formfactor::RowSampling rowSampling(*tracer, patches, sampling);
      formfactor::SampleTally tally;
      formfactor::Statistics statistics;
      int64_t sampled = 0;
      double formFactorSeconds = 0;
      for (int64_t rays : settings.rays) {
        start = MPI_Wtime();
        formfactor::SampleTally more;
        runCollectively(console.comm(), [&] {
          more = rowSampling.sample(owned.begin, owned.end, sampled, rays - sampled, statistics);
        });
        tally = sampled == 0 ? std::move(more) : formfactor::mergeSamples(tally, more);
        sampled = rays;
        formFactorSeconds += slowestRank(comm, MPI_Wtime() - start);
        const formfactor::SparseRows rows = formfactor::toFormFactors(tally);

        for (double rtol : settings.rtols) {
          start = MPI_Wtime();
          formfactor::SparseRows solved = rows;
          if (solve::needsReciprocity(settings.solver)) {
            solve::RepairReport repair;
            solved = solve::repairFormFactors(solved, area, {true, 0.0}, repair, comm);
          }
          solve::Options options;
          options.solver = settings.solver;
          options.rtol = rtol;
          // The sampling error as the solve estimates it, to set beside the measured one.
          options.samplesPerRow = rays;
          options.calibrate = [&](const std::vector<Rgb>& radiosity,
                                  const std::vector<Rgb>& indirect,
                                  const std::vector<Rgb>& direct) {
            formfactor::Options replicate = sampling;
            replicate.raysPerPatch = rays;
            return calibrateSamplingError(comm, *tracer, patches, owned, replicate, radiosity,
                                          indirect, direct)
                .scale;
          };
          solve::Report report;
          const LocalSolution solution = solve::solveRadiosity(
              std::move(solved), patchCount, reflectance, emission, area, options, report);
          const double solveSeconds = slowestRank(comm, MPI_Wtime() - start);
          const ChannelErrors b = compare(comm, solution.radiosity, reference.radiosity, area,
                                          reflectance, solution.radiosityStderr);
          const ChannelErrors h =
              compare(comm, solution.irradiance, reference.irradiance, area, reflectance, {});
          const double seconds = meshSeconds + formFactorSeconds + solveSeconds;

          csv << '"' << settings.scene << '"' << ',' << number(maxArea) << ',' << patchCount << ','
              << formfactor::estimatorName(estimator) << ',' << rays << ','
              << solve::solverName(settings.solver) << ',' << number(rtol) << ','
              << number(meshSeconds) << ',' << number(formFactorSeconds) << ','
              << number(solveSeconds) << ',' << number(seconds) << ',' << report.iterations << ','
              << number(report.residual) << ',' << number(report.errorBound);
          for (const ChannelErrors* errors : {&b, &h}) {
            for (const Rgb* v : {&errors->rms, &errors->largest})
              for (int c = 0; c < 3; ++c) csv << ',' << number((*v)[c]);
          }
          for (const auto* v : {&report.samplingErrorB, &report.samplingErrorH})
            for (int c = 0; c < 3; ++c) csv << ',' << number((*v)[c]);
          for (int c = 0; c < 3; ++c) csv << ',' << number(b.covered[c]);
          csv << '\n';
          if (!settings.quiet) {
            console.info(std::string("  ") + formfactor::estimatorName(estimator) + ", " +
                         std::to_string(rays) + " rays, rtol " + number(rtol) + ": B error " +
                         number(worst(b.rms)) + " (estimated " + number(report.relativeStderr) +
                         "), largest " + number(worst(b.largest)) + "; H error " +
                         number(worst(h.rms)) + "; " + number(seconds) + " s");
          }
          std::string label = formfactor::estimatorName(estimator);
          if (settings.rtols.size() > 1) label += ", rtol " + number(rtol);
          if (maxAreas.size() > 1) label += ", max area " + number(maxArea);
          errorAgainstTime.add(label + ": B measured", seconds, worst(b.rms));
          errorAgainstTime.add(label + ": B estimated", seconds, report.relativeStderr, true);

          // The error where the solver stopped, at each --rtol, for the most rays of the first
          // estimator and mesh: the solver's error against its iterations and time.
          if (maxArea == maxAreas.front() && estimator == settings.estimators.front() &&
              rays == settings.rays.back()) {
            solverError.x.push_back(std::max(
                1.0, static_cast<double>(report.iterations) / std::max(1, report.channelsSolved)));
            solverError.y.push_back(worst(b.rms));
            solverErrorByTime.x.push_back(solveSeconds);
            solverErrorByTime.y.push_back(worst(b.rms));
          }
          // The solver's own curve: the most accurate setting of the first estimator and mesh.
          if (maxArea == maxAreas.front() && estimator == settings.estimators.front() &&
              rays == settings.rays.back() &&
              rtol == *std::min_element(settings.rtols.begin(), settings.rtols.end())) {
            const SolveHistory& history = report.history;
            for (int c = 0; c < 3; ++c) {
              PlotSeries byIteration{std::string("residual, ") + kChannelNames[c], {}, {}};
              PlotSeries byTime = byIteration;
              for (size_t k = 0; k < history.size(); ++k) {
                if (history.channel[k] != c) continue;
                byIteration.x.push_back(static_cast<double>(history.iteration[k] + 1));
                byIteration.y.push_back(history.residual[k]);
                byTime.x.push_back(history.seconds[k]);
                byTime.y.push_back(history.residual[k]);
              }
              if (!byIteration.x.empty()) {
                solverCurves.push_back(byIteration);
                solverTimeCurves.push_back(byTime);
              }
            }
          }
        }
      }
    }
  }

  solverCurves.push_back(solverError);
  solverTimeCurves.push_back(solverErrorByTime);
  runCollectively(console.comm(), [&] {
    if (!console.isRoot()) return;
    std::vector<std::pair<std::string, std::string>> files{{settings.output, csv.str()}};
    if (!settings.plot.empty()) {
      PlotPanel accuracy{"Error against run time: " + settings.scene,
                         "wall time: mesh + form factors + solve (s)",
                         "RMS relative error of B over reflecting patches (estimate dashed)",
                         true,
                         true,
                         errorAgainstTime.list()};
      PlotPanel iterations{std::string("The solver (") + solve::solverName(settings.solver) +
                               "), most accurate setting",
                           "iteration",
                           "relative residual; error of B",
                           true,
                           true,
                           solverCurves};
      PlotPanel time{
          "The solver against time", "solve time (s)", "relative residual; error of B", true, true,
          solverTimeCurves};
      files.emplace_back(settings.plot, svgPlot({accuracy, iterations, time}));
    }
    writeTextFilesAtomically(files);
  });
  console.info("wrote " + settings.output + (settings.plot.empty() ? "" : " and " + settings.plot));
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
