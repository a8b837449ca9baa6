// `radiosity study`: what accuracy each setting buys and at what cost. The scene is loaded once,
// each mesh refined and its BVH built once, and for each estimator the rays are added to the
// same rows setting after setting (the sampling is extensible), so a sweep over rays costs what
// its largest setting costs. Every setting's B and H are compared with the scene's exact answer
// (jobs/study/exact_answers.h) or with a reference result file. Each mesh is made and laid out by
// the same stages as the solve pipeline's (run/mesh_stage.h, run/tracing_stage.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/channels.h"
#include "core/error.h"
#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "io/store/result.h"
#include "io/store/scene_file.h"
#include "jobs/commands.h"
#include "jobs/study/exact_answers.h"
#include "jobs/study/reference_match.h"
#include "jobs/study/setting_result.h"
#include "jobs/study/study_plot.h"
#include "measure/light_error.h"
#include "parallel/collective.h"
#include "partition/partition.h"
#include "run/console.h"
#include "run/memory_check.h"
#include "run/mesh_stage.h"
#include "run/output_paths.h"
#include "run/tracing_stage.h"
#include "solve/error_calibration.h"
#include "solve/solve.h"

namespace radiosity::jobs {

namespace {

// The answer each setting is compared with: for every patch, then for this rank's rows.
struct Reference {
  std::vector<Rgb> radiosity, irradiance;
  std::string how;
  // Keeps the rows `owned` only.
  void keep(partition::PatchRange owned) {
    radiosity.assign(radiosity.begin() + owned.begin, radiosity.begin() + owned.end);
    irradiance.assign(irradiance.begin() + owned.begin, irradiance.begin() + owned.end);
  }
};

Reference referenceFor(const StudySettings& settings, const Mesh& patches) {
  Reference reference;
  if (!settings.reference.empty()) {
    Result result = readResult(settings.reference);
    // Positions and materials too: another scene with as many triangles numbers them alike.
    if (const std::string difference = meshDifference(result.mesh, patches); !difference.empty()) {
      throw InputError(
          settings.reference + ": its mesh is not this study's (" + difference +
          "): solve the same scene with the same --max-area and --refine-rounds 0, which keeps "
          "the first mesh");
    }
    reference.radiosity = std::move(result.radiosity);
    reference.irradiance = std::move(result.irradiance);
    reference.how = "reference " + settings.reference;
  } else {
    std::optional<ExactAnswer> exact = exactAnswer(settings.scene, patches);
    if (!exact) {
      throw InputError(settings.scene +
                       ": no exact answer is known for this scene; give --reference FILE.h5, a "
                       "high-effort solve of the same scene and --max-area");
    }
    reference.radiosity = std::move(exact->radiosity);
    reference.irradiance = std::move(exact->irradiance);
    reference.how = exact->how;
  }
  return reference;
}

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
      errors.largest[c] = std::max(
          errors.largest[c],
          relativeToFloor(std::abs(gap[i][c]), exact[i][c], kLightErrorFloorShare * mean[c]));
      counts[3 + c] += 1;
      if (!standardError.empty() && std::abs(gap[i][c]) <= 2 * standardError[i][c]) counts[c] += 1;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, errors.largest.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, counts, 6, MPI_DOUBLE, MPI_SUM, comm);
  for (int c = 0; c < 3; ++c) errors.covered[c] = counts[3 + c] > 0 ? counts[c] / counts[3 + c] : 0;
  return errors;
}

std::string csvHeader() {
  std::string header =
      "scene,max_area,patches,estimator,rays,solver,rtol,seconds_mesh,seconds_formfactors,"
      "seconds_solve,seconds_total,iterations,residual,error_bound";
  for (const char* what :
       {"B_error", "B_max", "H_error", "H_max", "B_estimate", "H_estimate", "B_coverage"})
    for (const char* channel : kChannelNames) header += std::string(",") + what + "_" + channel;
  return header + "\n";
}

// One mesh of the sweep, ready to sample: its patches (in the tracing frame), this rank's rows
// and their data, the answer they are compared with, the tracer and the time meshing took.
struct StudyMesh {
  StudyMesh(const StudySettings& settings, const run::Console& console, const Mesh& scene,
            double maxArea);
  StudyMesh(const StudyMesh&) = delete;
  StudyMesh& operator=(const StudyMesh&) = delete;

  double maxArea = 0;
  double seconds = 0;
  Mesh patches;
  int64_t patchCount = 0;
  partition::PatchRange owned;
  Reference reference;
  run::OwnedPatches local;
  std::unique_ptr<trace::SceneTracer> tracer;
};

StudyMesh::StudyMesh(const StudySettings& settings, const run::Console& console, const Mesh& scene,
                     double maxArea)
    : maxArea(maxArea) {
  const MPI_Comm comm = console.comm();
  run::checkMeshFits(comm, scene.totalArea(), scene.triangleCount(), 0, maxArea,
                     "--max-area " + number(maxArea));
  const double start = MPI_Wtime();
  // Meshed as `solve` meshes with --max-area (cut along contacts, then refined), so that a
  // solve's result can be the reference.
  patches = run::meshScene({.console = console,
                            .scene = scene,
                            .maxArea = maxArea,
                            .cutContacts = true,
                            .surfaceShare = 0})
                .patches;
  seconds = run::slowestRank(comm, MPI_Wtime() - start);
  patchCount = patches.triangleCount();
  runCollectively(console.comm(), [&] { reference = referenceFor(settings, patches); });
  console.info("study: " + std::to_string(patchCount) + " patches (max area " + number(maxArea) +
               "), compared with the " + reference.how);
  normaliseForTracing(patches);  // (the answer at any scale is the answer at scale 1)
  // No split given: the rows by count (no pilot: the same blocks for every setting).
  run::TracedRows laid =
      run::layOutRows({.console = console, .patches = patches, .threads = settings.threads});
  tracer = std::move(laid.tracer);
  owned = laid.owned;
  local = std::move(laid.local);
  reference.keep(owned);
}

// Solves with the form factors `rows` (`rays` samples per row, by `sampling`) at `rtol` and
// compares B and H with the mesh's reference.
SettingResult solveSetting(const StudySettings& settings, MPI_Comm comm, const StudyMesh& mesh,
                           const formfactor::Options& sampling, const formfactor::SparseRows& rows,
                           int64_t rays, double rtol, double formFactorSeconds) {
  const std::vector<double>& area = mesh.local.area;
  const std::vector<Rgb>& reflectance = mesh.local.reflectance;
  SettingResult result;
  result.estimator = sampling.estimator;
  result.rays = rays;
  result.rtol = rtol;
  result.formFactorSeconds = formFactorSeconds;
  const double start = MPI_Wtime();
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
  options.calibrate = [&](const std::vector<Rgb>& radiosity) {
    formfactor::Options replicate = sampling;
    replicate.raysPerPatch = rays;
    return solve::calibrateSamplingError(comm, *mesh.tracer, mesh.patches, mesh.owned, replicate,
                                         radiosity)
        .scale;
  };
  const LocalSolution solution =
      solve::solveRadiosity(std::move(solved), mesh.patchCount, reflectance, mesh.local.emission,
                            area, options, result.report);
  result.solveSeconds = run::slowestRank(comm, MPI_Wtime() - start);
  result.b = compare(comm, solution.radiosity, mesh.reference.radiosity, area, reflectance,
                     solution.radiosityStderr);
  result.h = compare(comm, solution.irradiance, mesh.reference.irradiance, area, reflectance, {});
  result.seconds = mesh.seconds + formFactorSeconds + result.solveSeconds;
  return result;
}

// The setting's row of the CSV (csvHeader's columns).
std::string csvRow(const StudySettings& settings, const StudyMesh& mesh,
                   const SettingResult& result) {
  const solve::Report& report = result.report;
  std::ostringstream row;
  row << '"' << settings.scene << '"' << ',' << number(mesh.maxArea) << ',' << mesh.patchCount
      << ',' << formfactor::estimatorName(result.estimator) << ',' << result.rays << ','
      << solve::solverName(settings.solver) << ',' << number(result.rtol) << ','
      << number(mesh.seconds) << ',' << number(result.formFactorSeconds) << ','
      << number(result.solveSeconds) << ',' << number(result.seconds) << ',' << report.iterations
      << ',' << number(report.residual) << ',' << number(report.errorBound);
  for (const ChannelErrors* errors : {&result.b, &result.h}) {
    for (const Rgb* v : {&errors->rms, &errors->largest})
      for (int c = 0; c < 3; ++c) row << ',' << number((*v)[c]);
  }
  for (const auto* v : {&report.samplingErrorB, &report.samplingErrorH})
    for (int c = 0; c < 3; ++c) row << ',' << number((*v)[c]);
  for (int c = 0; c < 3; ++c) row << ',' << number(result.b.covered[c]);
  row << '\n';
  return row.str();
}

// The setting's line of the log.
std::string progressLine(const SettingResult& result) {
  return std::string("  ") + formfactor::estimatorName(result.estimator) + ", " +
         std::to_string(result.rays) + " rays, rtol " + number(result.rtol) + ": B error " +
         number(worst(result.b.rms)) + " (estimated " + number(result.report.relativeStderr) +
         "), largest " + number(worst(result.b.largest)) + "; H error " +
         number(worst(result.h.rms)) + "; " + number(result.seconds) + " s";
}

// The sweep of one estimator on one mesh: the rays are added to the same rows setting after
// setting, and each is solved at every --rtol.
void sweepEstimator(const StudySettings& settings, const run::Console& console,
                    const StudyMesh& mesh, formfactor::Estimator estimator, std::ostringstream& csv,
                    StudyPlot& plot) {
  const MPI_Comm comm = console.comm();
  formfactor::Options sampling;
  sampling.seed = settings.seed;
  sampling.threads = settings.threads;
  sampling.estimator = estimator;
  formfactor::RowSampling rowSampling(*mesh.tracer, mesh.patches, sampling);
  formfactor::SampleTally tally;
  formfactor::Statistics statistics;
  int64_t sampled = 0;
  double formFactorSeconds = 0;
  for (int64_t rays : settings.rays) {
    const double start = MPI_Wtime();
    formfactor::SampleTally more;
    runCollectively(console.comm(), [&] {
      more =
          rowSampling.sample(mesh.owned.begin, mesh.owned.end, sampled, rays - sampled, statistics);
    });
    tally = sampled == 0 ? std::move(more) : formfactor::mergeSamples(tally, more);
    sampled = rays;
    formFactorSeconds += run::slowestRank(comm, MPI_Wtime() - start);
    const formfactor::SparseRows rows = formfactor::toFormFactors(tally);

    for (double rtol : settings.rtols) {
      const SettingResult result =
          solveSetting(settings, comm, mesh, sampling, rows, rays, rtol, formFactorSeconds);
      csv << csvRow(settings, mesh, result);
      console.info(progressLine(result));
      plot.add(mesh.maxArea, result);
    }
  }
}

}  // namespace

int runStudy(const StudySettings& requested, const run::Console& console) {
  StudySettings settings = requested;
  std::sort(settings.rays.begin(), settings.rays.end());
  settings.rays.erase(std::unique(settings.rays.begin(), settings.rays.end()), settings.rays.end());
  runCollectively(console.comm(), [&] {
    run::checkOutputs({settings.output, settings.plot}, {settings.scene, settings.reference});
  });

  Mesh scene;
  scene = loadScene(settings.scene, console.comm());
  // The files the scene named (an OBJ's mtllib, whatever their names) are inputs too.
  runCollectively(console.comm(), [&] {
    run::checkOutputs({settings.output, settings.plot}, scene.sourceFiles);
  });
  std::vector<double> maxAreas = settings.maxAreas;
  if (maxAreas.empty()) maxAreas.push_back(scene.totalArea() / run::kAutoPatchDivisor);

  std::ostringstream csv;
  csv << csvHeader();
  StudyPlot plot(settings, maxAreas);
  for (double maxArea : maxAreas) {
    const StudyMesh mesh(settings, console, scene, maxArea);
    for (formfactor::Estimator estimator : settings.estimators)
      sweepEstimator(settings, console, mesh, estimator, csv, plot);
  }

  runCollectively(console.comm(), [&] {
    if (!console.isRoot()) return;
    std::vector<std::pair<std::string, std::string>> files{{settings.output, csv.str()}};
    if (!settings.plot.empty()) files.emplace_back(settings.plot, plot.svg());
    writeTextFilesAtomically(files);
  });
  console.info("wrote " + settings.output + (settings.plot.empty() ? "" : " and " + settings.plot));
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
