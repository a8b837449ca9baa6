// `radiosity solve`: the pipeline in order: load, mesh, partition, form factors, solve, write.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/result.h"
#include "io/store/checkpoint.h"
#include "jobs/checkpointing.h"
#include "jobs/commands.h"
#include "jobs/discretisation_error.h"
#include "jobs/error_calibration.h"
#include "jobs/formfactor_stage.h"
#include "jobs/memory_check.h"
#include "jobs/output_paths.h"
#include "jobs/safe_points.h"
#include "jobs/stage_reports.h"
#include "partition/partition.h"
#include "solve/solve.h"

namespace radiosity::jobs {

namespace {

std::string defaultOutput(const std::string& scene) {
  std::string stem =
      scene.rfind("builtin:", 0) == 0
          ? scene.substr(
                8, scene.find('?') == std::string::npos ? std::string::npos : scene.find('?') - 8)
          : std::filesystem::path(scene).stem().string();
  return stem + ".h5";
}

std::string describeSettings(const SolveSettings& s, double maxArea, int ranks) {
  std::ostringstream text;
  text << "scene = " << s.scene << "\noutput = " << s.output << "\nmax-area = " << maxArea
       << "\nrays = " << s.raysPerPatch << "\nseed = " << s.seed << "\nestimator = " << s.estimator
       << "\nthreads = " << s.threads << "\nsolver = " << (s.solver.empty() ? "auto" : s.solver)
       << "\nrtol = ";
  if (s.rtol > 0) {
    text << s.rtol;
  } else {
    text << "auto";
  }
  text << "\nranks = " << ranks << "\n";
  if (s.patches > 0) text << "patches = " << s.patches << "\n";
  if (s.saveFormFactors) text << "save-formfactors = true\n";
  if (s.reciprocity) text << "reciprocity = true\n";
  if (s.dropThreshold > 0) text << "drop-threshold = " << s.dropThreshold << "\n";
  if (s.targetError > 0) text << "target-error = " << s.targetError << "\n";
  return text.str();
}

// The rays per patch expected to bring the sampling error to 80 % of the target: it falls like
// N^-2/3 with the scrambled Sobol' points (docs/accuracy.md), so N grows by the error's ratio to
// the power 3/2; at least doubled, at most ×16 per round and 2^24 in all.
int64_t nextRayCount(int64_t rays, double estimated, double target) {
  const double factor = std::clamp(std::pow(estimated / (0.8 * target), 1.5), 2.0, 16.0);
  return std::min<int64_t>(int64_t{1} << 24, static_cast<int64_t>(std::ceil(rays * factor)));
}

formfactor::Options samplingOptions(const SolveSettings& s) {
  formfactor::Options options;
  options.raysPerPatch = s.raysPerPatch;
  options.seed = s.seed;
  options.estimator = s.estimator == "mis" ? formfactor::Estimator::kEmitterMis
                                           : formfactor::Estimator::kHemisphere;
  options.threads = s.threads;
  return options;
}

}  // namespace

int runSolve(const SolveSettings& requested, const Console& console) {
  SolveSettings settings = requested;
  if (settings.output.empty()) settings.output = defaultOutput(settings.scene);
  // Outputs that cannot be written, or would overwrite an input or a device, are refused now,
  // not after the solve. (A checkpoint may be the file a restart reads: that is how a requeued
  // job goes on.)
  if (!settings.meshOnly) {
    runOnAllRanks(console, [&] {
      const std::string mtl = std::filesystem::path(settings.scene).replace_extension(".mtl");
      checkOutputs({settings.output}, {settings.scene, mtl, settings.restart});
      checkOutputs({settings.checkpoint}, {settings.scene, mtl});
      checkOutputs({settings.output, settings.checkpoint}, {});
    });
  }
  const MPI_Comm comm = console.comm();
  ResultAttributes attributes;
  double stageStart = MPI_Wtime();
  auto endStage = [&](const char* name) {
    double now = MPI_Wtime();
    attributes.stageSeconds[name] += slowestRank(comm, now - stageStart);  // summed over rounds
    stageStart = now;
  };

  // 1. Load the scene: every rank holds the whole geometry.
  Mesh scene;
  {
    solve::ScopedStage stage("Load scene");
    runOnAllRanks(console, [&] { scene = loadScene(settings.scene); });
    for (const std::string& warning : scene.warnings) console.warn(warning);
    endStage("load");
  }

  // 2. Mesh: refine to the area bound (or to about --patches patches) and number the patches
  // along a space-filling curve.
  Mesh patches;
  double maxArea = settings.maxArea > 0 ? settings.maxArea : scene.totalArea() / kAutoPatchDivisor;
  {
    char option[64];
    if (settings.patches > 0) {
      std::snprintf(option, sizeof option, "--patches %lld",
                    static_cast<long long>(settings.patches));
    } else {
      std::snprintf(option, sizeof option, "--max-area %g", maxArea);
    }
    checkMeshFits(comm, scene.totalArea(), scene.triangleCount(), settings.patches, maxArea,
                  option);
  }
  {
    solve::ScopedStage stage("Mesh");
    partition::MeshingReport meshing;
    runOnAllRanks(console, [&] {
      Mesh refined = settings.patches > 0
                         ? partition::refineToCount(scene, settings.patches, &meshing)
                         : partition::refine(scene, maxArea, &meshing);
      scene = Mesh();  // not needed any more: free it before the reordered copy
      patches = partition::orderAlongCurve(std::move(refined));
    });
    if (settings.patches > 0) maxArea = meshing.areaBound;
    reportMeshing(console, meshing, settings.patches, maxArea);
    endStage("mesh");
  }
  if (settings.meshOnly) {
    std::ostringstream times;
    times << "mesh only, nothing written; stage times (s): load " << attributes.stageSeconds["load"]
          << " mesh " << attributes.stageSeconds["mesh"];
    console.info(times.str());
    return exit_code::kOk;
  }
  const int64_t patchCount = patches.triangleCount();
  const partition::PatchRange owned =
      partition::blockOf(patchCount, console.rank(), console.ranks());
  // The estimator: the one named, or the one that serves the scene (the log says why).
  if (settings.estimator == "auto") {
    const formfactor::EstimatorChoice choice = formfactor::chooseEstimator(patches);
    settings.estimator = choice.estimator == formfactor::Estimator::kEmitterMis ? "mis" : "hemisphere";
    console.info("form factors: no --estimator given: " + settings.estimator + ", as " +
                 choice.reason);
  }
  if (!settings.quiet) console.info(describeSettings(settings, maxArea, console.ranks()));
  // MIS casts two rays a sample (formfactor.h).
  checkFormFactorsFit(comm, patchCount,
                      settings.raysPerPatch * (settings.estimator == "mis" ? 2 : 1),
                      "--rays " + std::to_string(settings.raysPerPatch));

  // Checkpoints: the run's state goes to --checkpoint at safe points (periodically, on a
  // signal, at the end); --restart takes a state back, on any number of ranks.
  SafePoints safePoints(comm, !settings.checkpoint.empty(), settings.checkpointEvery);
  const std::map<std::string, std::string> identity = runIdentity(settings, patches, maxArea);
  // Traced in the scene's own frame (io/core/mesh.h, TracingFrame), so that the answer at any scale is
  // the answer at scale 1; the result file gets the user's coordinates back.
  const std::vector<Vec3> worldVertices = patches.vertices;
  normaliseForTracing(patches);
  Checkpoint restored;
  if (!settings.restart.empty()) {
    restored = readCheckpoint(comm, settings.restart, owned.begin, owned.end);
    runOnAllRanks(console, [&] {
      checkResumable(settings.restart, restored, identity, patchCount, settings.raysPerPatch);
    });
    reportRestart(console, settings.restart, restored, patchCount, settings.raysPerPatch);
  }
  // (taken before the form-factor stage takes the rows over)
  std::optional<solve::SolveProgress> resume =
      settings.restart.empty() ? std::nullopt
                               : savedProgress(restored, settings.raysPerPatch, comm);
  // `together`: staged with the result, renamed with it (the final state); otherwise written
  // and renamed at once.
  auto writeState = [&](const char* stage, PartialRows& state,
                        const solve::SolveProgress* progress, CollectiveOutputs* together) {
    const double start = MPI_Wtime();
    Checkpoint checkpoint;
    checkpoint.stage = stage;
    checkpoint.identity = identity;
    checkpoint.patchCount = patchCount;
    checkpoint.rows = std::move(state.tally);  // lent to the checkpoint, given back below
    checkpoint.rowSamples = std::move(state.rowSamples);
    if (progress) {
      checkpoint.channelState = progress->channelState;
      checkpoint.radiosity = progress->radiosity;
      checkpoint.history = progress->history;
    } else {
      checkpoint.radiosity.assign(owned.size(), Rgb{0, 0, 0});
    }
    try {
      if (together)
        stageCheckpoint(*together, settings.checkpoint, checkpoint);
      else
        writeCheckpoint(comm, settings.checkpoint, checkpoint);
    } catch (...) {
      state.tally = std::move(checkpoint.rows);
      state.rowSamples = std::move(checkpoint.rowSamples);
      throw;
    }
    state.tally = std::move(checkpoint.rows);
    state.rowSamples = std::move(checkpoint.rowSamples);
    reportCheckpoint(console, settings.checkpoint, stage, state.rowSamples,
                     slowestRank(comm, MPI_Wtime() - start));
  };
  auto stopped = [&] {
    return Error(exit_code::kStoppedBySignal, "stopped by " + safePoints.signalName() +
                                                  "; the run's state is in " + settings.checkpoint +
                                                  ": resume with --restart " + settings.checkpoint);
  };

  std::vector<double> area(owned.size());
  for (int64_t r = 0; r < owned.size(); ++r) area[r] = patches.area(owned.begin + r);
  std::vector<Rgb> reflectance(patches.reflectance.begin() + owned.begin,
                               patches.reflectance.begin() + owned.end);
  std::vector<Rgb> emission(patches.emission.begin() + owned.begin,
                            patches.emission.begin() + owned.end);
  std::unique_ptr<formfactor::SceneTracer> tracer;
  runOnAllRanks(console, [&] {
    tracer = std::make_unique<formfactor::SceneTracer>(patches, settings.threads);
  });

  // Rounds of form factors and solve: one, or with --target-error as many as it takes, each
  // adding samples to the same rows (the sequence is extensible) and starting from the last B.
  PartialRows carried = savedRows(restored);
  restored = Checkpoint();
  formfactor::SparseRows rows;
  std::vector<int64_t> rowSumHistogram;
  PartialRows finishedRows;
  solve::Options solveOptions;
  solveOptions.solver = settings.solver;
  // Without --rtol, each channel stops where the solver's error is a tenth of the sampling
  // error (solve::Options::adaptiveRtol).
  solveOptions.rtol = settings.rtol > 0 ? settings.rtol : solve::kFirstAdaptiveRtol;
  solveOptions.adaptiveRtol = settings.rtol <= 0;
  CalibrationReport calibration;
  solveOptions.calibrate = [&](const std::vector<Rgb>& radiosity,
                               const std::vector<Rgb>& indirect, const std::vector<Rgb>& direct) {
    calibration = calibrateSamplingError(comm, *tracer, patches, owned, samplingOptions(settings),
                                         radiosity, indirect, direct);
    return calibration.scale;
  };
  DiscretisationReport discretisation;
  solveOptions.discretisation = [&](const std::vector<Rgb>& irradiance, std::vector<Rgb>& error,
                                    std::vector<Rgb>& variance) {
    estimateDiscretisationError(comm, *tracer, patches, owned, settings.seed,
                                discretisationRays(settings.raysPerPatch), irradiance, error,
                                variance, discretisation);
  };
  solveOptions.safePoint = [&] { return safePoints.poll(); };
  solveOptions.save = [&](const solve::SolveProgress& progress) {
    writeState("solve", finishedRows, &progress, nullptr);
    safePoints.checkpointWritten();
  };
  std::string solverChoice;
  solve::Report report;
  LocalSolution solution;
  for (int round = 0;; ++round) {
    // 3. Form factors: this rank's rows, traced against the whole scene, in pieces with a safe
    // point after each; rows sampled before (a checkpoint, an earlier round) are extended.
    formfactor::SampleTally tally;
    formfactor::Statistics statistics;
    {
      solve::ScopedStage stage("Form factors");
      ProgressReporter progress(console, owned.size(), settings.raysPerPatch);
      std::function<void(int64_t)> callback;
      if (!settings.quiet) callback = [&](int64_t done) { progress(done); };
      try {
        tally = sampleOwnedRows(
            comm, *tracer, patches, owned, samplingOptions(settings), std::move(carried),
            safePoints, [&](PartialRows& state) { writeState("formfactors", state, nullptr, nullptr); },
            statistics, callback);
      } catch (const solve::SolveStopped&) {
        throw stopped();
      }
      rows = formfactor::toFormFactors(tally);
      formfactor::addRowSums(rows, statistics);
      endStage("formfactors");
      rowSumHistogram = reportFormFactors(console, patches, rows, statistics,
                                          attributes.stageSeconds["formfactors"]);
    }
    // The rows stay at hand for checkpoints (and a later restart with more rays) and for the
    // next round.
    finishedRows = PartialRows();
    if (!settings.checkpoint.empty() || settings.targetError > 0) {
      finishedRows.tally = std::move(tally);
      finishedRows.rowSamples.assign(owned.size(), settings.raysPerPatch);
    }
    tally = formfactor::SampleTally();

    // 3a. The solver: the one named, or one chosen for the scene. CG needs a reciprocal F.
    if (solveOptions.solver.empty()) {
      const solve::SolverChoice choice =
          solve::chooseSolver(rows, reflectance, settings.reciprocity, comm);
      solveOptions.solver = choice.solver;
      solverChoice = choice.reason;
      console.info("solve: no --solver given: " + choice.solver + ", as " + choice.reason);
    }
    if (solve::needsReciprocity(solveOptions.solver) && !settings.reciprocity) {
      settings.reciprocity = true;
      console.info("solve: " + solveOptions.solver +
                   " needs a reciprocal F (cg: a symmetric form; chebyshev: real eigenvalues): "
                   "enforcing reciprocity (as with --reciprocity)");
    }

    // 3b. Reciprocity and sparsification: symmetrise A_i F_ij = A_j F_ji and/or drop small
    // F_ij, then restore every row's sum (Lawson's least-squares correction).
    if (settings.reciprocity || settings.dropThreshold > 0) {
      solve::ScopedStage stage("Repair form factors");
      solve::RepairReport repair;
      rows = solve::repairFormFactors(rows, area, {settings.reciprocity, settings.dropThreshold},
                                      repair, comm);
      endStage("repair");
      reportRepair(console, repair, attributes.stageSeconds["repair"]);
    }

    // 4. Solve (I − diag(ρ_c) F) B_c = E_c per channel, and estimate B's sampling error.
    {
      solve::ScopedStage stage("Solve");
      solveOptions.resume = resume ? &*resume : nullptr;
      solveOptions.samplesPerRow = settings.raysPerPatch;
      // PETSc takes F over; our rows are kept only when the result file is to hold them.
      try {
        solution =
            solve::solveRadiosity(settings.saveFormFactors ? rows : std::move(rows), patchCount,
                                  reflectance, emission, area, solveOptions, report);
      } catch (const solve::SolveStopped&) {
        throw stopped();
      }
      endStage("solve");
      reportSolve(console, report, attributes.stageSeconds["solve"]);
      reportCalibration(console, calibration, discretisation, report);
    }

    // --target-error: more rays while the estimated error is above the target and rays can
    // bring it there; the discretisation error they cannot reduce.
    if (settings.targetError <= 0 || report.relativeStderr <= settings.targetError) break;
    char text[400];
    const double reachable = std::pow(0.8 * settings.targetError, 2) -
                             std::pow(report.discretisationShare, 2);
    if (reachable <= 0.04 * std::pow(settings.targetError, 2)) {
      std::snprintf(text, sizeof text,
                    "target error %.3g not reached: the estimated error is %.3g, of which the "
                    "discretisation error (%.3g) is more than rays can take away; refine the mesh "
                    "(a smaller --max-area, or more --patches)",
                    settings.targetError, report.relativeStderr, report.discretisationShare);
      console.warn(text);
      break;
    }
    const int64_t next =
        nextRayCount(settings.raysPerPatch, report.samplingShare, std::sqrt(reachable) / 0.8);
    if (next <= settings.raysPerPatch) {
      std::snprintf(text, sizeof text,
                    "target error %.3g not reached: the estimated error is %.3g at %lld rays per "
                    "patch, the most allowed",
                    settings.targetError, report.relativeStderr,
                    static_cast<long long>(settings.raysPerPatch));
      console.warn(text);
      break;
    }
    std::snprintf(text, sizeof text,
                  "target error: estimated %.3g > %.3g at %lld rays per patch (sampling %.3g, "
                  "discretisation %.3g); going on with %lld",
                  report.relativeStderr, settings.targetError,
                  static_cast<long long>(settings.raysPerPatch), report.samplingShare,
                  report.discretisationShare, static_cast<long long>(next));
    console.info(text);
    carried = std::move(finishedRows);
    resume = solve::SolveProgress{{1, 1, 1}, solution.radiosity, report.history};
    settings.raysPerPatch = next;
  }

  // The finished run's state, before the result: a later --restart with more --rays adds to
  // these rows, and a run whose last checkpoint could not be written (a full disk) fails
  // without leaving a result that looks complete.
  // The final checkpoint and the result are renamed together, once both are complete.
  CollectiveOutputs outputs(comm);
  if (!settings.checkpoint.empty()) {
    const solve::SolveProgress done{{2, 2, 2}, solution.radiosity, report.history};
    writeState("done", finishedRows, &done, &outputs);
  }

  // 5. Write the result, each rank its own slab.
  attributes.ranks = console.ranks();
  attributes.raysPerPatch = settings.raysPerPatch;
  attributes.seed = settings.seed;
  attributes.solver = report.solver;
  attributes.solverChoice = solverChoice;
  attributes.history = report.history;
  attributes.solveFigures = {{"error_bound", report.errorBound},
                             {"error_estimate", report.relativeStderr},
                             {"sampling_error", report.samplingShare},
                             {"discretisation_error", report.discretisationShare},
                             {"error_calibration_rays", static_cast<double>(calibration.rays)},
                             {"contraction", report.contraction},
                             {"condition_estimate", report.conditionEstimate},
                             {"unknowns", static_cast<double>(report.unknowns)},
                             {"matrix_products", static_cast<double>(report.matrixProducts)},
                             {"nonzero_products", static_cast<double>(report.nonzeroProducts)},
                             {"channels_solved", static_cast<double>(report.channelsSolved)}};
  const char* channelNames[3] = {"red", "green", "blue"};
  for (int c = 0; c < 3; ++c) {
    const std::string channel = channelNames[c];
    attributes.solveFigures["sampling_error_B_" + channel] = report.samplingErrorB[c];
    attributes.solveFigures["sampling_error_H_" + channel] = report.samplingErrorH[c];
    attributes.solveFigures["discretisation_error_B_" + channel] = report.discretisationErrorB[c];
    attributes.solveFigures["error_estimate_B_" + channel] = report.errorB[c];
    attributes.solveFigures["error_estimate_H_" + channel] = report.errorH[c];
    attributes.solveFigures["error_scale_indirect_" + channel] = report.calibration.indirect[c];
    attributes.solveFigures["error_scale_direct_" + channel] = report.calibration.direct[c];
    attributes.solveFigures["solver_error_" + channel] = report.solverError[c];
  }
  attributes.iterations = report.iterations;
  attributes.residual = report.residual;
  attributes.converged = report.converged;
  attributes.leftOut = report.leftOut;
  attributes.scene = settings.scene;
  attributes.options = describeSettings(settings, maxArea, console.ranks());
  {
    solve::ScopedStage stage("Write result");
    // F goes to the file as it is, each rank its own rows.
    FormFactorOutput formFactors{rowSumHistogram, formfactor::rowSumBinEdges()};
    if (settings.saveFormFactors) formFactors.rows = &rows;
    patches.vertices = worldVertices;
    try {
      stageResult(outputs, settings.output, patches, solution, attributes, formFactors);
    } catch (const Error& e) {
      if (settings.checkpoint.empty()) throw;
      // The finished solve is not lost with the result: the complete checkpoint goes in place.
      outputs.commit();
      throw Error(e.exitCode(), std::string(e.what()) + "; the checkpoint " +
                                    settings.checkpoint +
                                    " holds the finished solve: run again with --restart " +
                                    settings.checkpoint + " to write the result");
    }
    outputs.commit();
    endStage("write");
  }
  std::ostringstream times;
  times << "wrote " << settings.output << "; stage times (s):";
  for (const char* stage : {"load", "mesh", "formfactors", "repair", "solve", "write"}) {
    auto seconds = attributes.stageSeconds.find(stage);  // repair only with its options
    if (seconds != attributes.stageSeconds.end()) times << " " << stage << " " << seconds->second;
  }
  console.info(times.str());
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
