// `radiosity solve`: the pipeline in order: load, mesh, partition, form factors, solve, write.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <utility>
#include <vector>

#include "formfactor/formfactor.h"
#include "io/io.h"
#include "jobs/commands.h"
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
       << "\nthreads = " << s.threads << "\nsolver = " << s.solver << "\nrtol = " << s.rtol
       << "\nranks = " << ranks << "\n";
  if (s.patches > 0) text << "patches = " << s.patches << "\n";
  if (s.saveFormFactors) text << "save-formfactors = true\n";
  if (s.reciprocity) text << "reciprocity = true\n";
  if (s.dropThreshold > 0) text << "drop-threshold = " << s.dropThreshold << "\n";
  return text.str();
}

/// "row sums of F (patches per bin from its lower edge): 0: 0 | 0.5: 3 | ...", on one line.
std::string histogramLine(const std::vector<int64_t>& counts, const std::vector<double>& edges) {
  std::ostringstream text;
  text.precision(10);  // tells 1 − 1e-9 from 1
  text << "row sums of F (patches per bin from its lower edge):";
  for (size_t k = 0; k < counts.size(); ++k) {
    text << (k == 0 ? " " : " | ");
    if (k < edges.size()) text << edges[k] << ": ";
    text << counts[k];
  }
  return text.str();
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

// Prints patches done, rays per second and time left, at most every two seconds.
class ProgressReporter {
 public:
  ProgressReporter(const Console& console, int64_t rows, int64_t raysPerRow)
      : console_(console),
        rows_(rows),
        raysPerRow_(raysPerRow),
        start_(MPI_Wtime()),
        last_(start_) {}
  void operator()(int64_t done) {
    double now = MPI_Wtime();
    if (now - last_ < 2.0 || done == rows_) return;
    last_ = now;
    double elapsed = now - start_;
    // Every rank has the same number of rows (±1), so rank 0's pace is the job's.
    double raysPerSecond = done * raysPerRow_ * console_.ranks() / elapsed;
    double left = elapsed * (rows_ - done) / done;
    char line[160];
    std::snprintf(line, sizeof line,
                  "  form factors: %lld/%lld patches on rank 0, %.3g rays/s, about %.0f s left",
                  static_cast<long long>(done), static_cast<long long>(rows_), raysPerSecond, left);
    console_.info(line);
  }

 private:
  const Console& console_;
  int64_t rows_, raysPerRow_;
  double start_, last_;
};

}  // namespace

int runSolve(const SolveSettings& requested, const Console& console) {
  SolveSettings settings = requested;
  if (settings.output.empty()) settings.output = defaultOutput(settings.scene);
  const MPI_Comm comm = console.comm();
  ResultAttributes attributes;
  double stageStart = MPI_Wtime();
  auto endStage = [&](const char* name) {
    double now = MPI_Wtime();
    attributes.stageSeconds[name] = slowestRank(comm, now - stageStart);
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
    char bound[120];
    if (settings.patches > 0) {
      std::snprintf(bound, sizeof bound, "--patches %lld: area bound %.4g%s",
                    static_cast<long long>(settings.patches), meshing.areaBound,
                    meshing.areaBound > 0 ? ", largest split first" : " (none: enough triangles)");
    } else {
      std::snprintf(bound, sizeof bound, "area bound %.4g", maxArea);
    }
    char line[300];
    std::snprintf(line, sizeof line,
                  "mesh: %lld input triangles -> %lld patches (%s; max area %.4g, worst aspect "
                  "%.2f)",
                  static_cast<long long>(meshing.inputTriangles),
                  static_cast<long long>(meshing.patches), bound, meshing.maxPatchArea,
                  meshing.worstAspectRatio);
    console.info(line);
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
  if (!settings.quiet) console.info(describeSettings(settings, maxArea, console.ranks()));

  // 3. Form factors: this rank's rows, traced against the whole scene.
  formfactor::SparseRows rows;
  formfactor::Statistics statistics;
  std::vector<int64_t> rowSumHistogram;
  {
    solve::ScopedStage stage("Form factors");
    runOnAllRanks(console, [&] {
      formfactor::SceneTracer tracer(patches);
      ProgressReporter progress(console, owned.size(), settings.raysPerPatch);
      formfactor::ProgressCallback callback;
      if (!settings.quiet) callback = [&](int64_t done) { progress(done); };
      rows = formfactor::computeRows(tracer, patches, owned.begin, owned.end,
                                     samplingOptions(settings), statistics, callback);
    });
    endStage("formfactors");
    int64_t counts[4] = {statistics.raysCast, statistics.backFaceHits, statistics.escapedRays,
                         rows.nonzeros()};
    MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_INT64_T, MPI_SUM, comm);
    double sums[1] = {statistics.sumRowSums}, lows[1] = {statistics.minRowSum},
           highs[1] = {statistics.maxRowSum};
    if (owned.size() == 0) lows[0] = 2.0;
    MPI_Allreduce(MPI_IN_PLACE, sums, 1, MPI_DOUBLE, MPI_SUM, comm);
    MPI_Allreduce(MPI_IN_PLACE, lows, 1, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, highs, 1, MPI_DOUBLE, MPI_MAX, comm);
    char line[300];
    std::snprintf(line, sizeof line,
                  "form factors: %lld rays in %.2f s (%.3g rays/s), %lld nonzeros (%.1f per "
                  "row, %.0f bytes per patch), row sums min %.4f mean %.4f max %.4f, %lld rays "
                  "escaped, %lld hit back faces",
                  static_cast<long long>(counts[0]), attributes.stageSeconds["formfactors"],
                  counts[0] / std::max(attributes.stageSeconds["formfactors"], 1e-9),
                  static_cast<long long>(counts[3]), double(counts[3]) / patchCount,
                  // CSR: a column index and a value per nonzero, a row pointer per row.
                  (16.0 * counts[3] + 8.0 * (patchCount + 1)) / patchCount, lows[0],
                  sums[0] / patchCount, highs[0], static_cast<long long>(counts[2]),
                  static_cast<long long>(counts[1]));
    console.info(line);
    // The row sums binned (closed scenes: all in the bin around 1), on every rank.
    rowSumHistogram = formfactor::rowSumHistogram(rows);
    MPI_Allreduce(MPI_IN_PLACE, rowSumHistogram.data(), static_cast<int>(rowSumHistogram.size()),
                  MPI_INT64_T, MPI_SUM, comm);
    console.info(histogramLine(rowSumHistogram, formfactor::rowSumBinEdges()));
    // Back-face hits per label (material/group), to name the faces whose winding looks wrong.
    std::vector<int64_t> byLabel = statistics.backFaceHitsByLabel;
    byLabel.resize(patches.hasLabels() ? patches.labelNames.size() : 0, 0);
    if (!byLabel.empty()) {
      MPI_Allreduce(MPI_IN_PLACE, byLabel.data(), static_cast<int>(byLabel.size()), MPI_INT64_T,
                    MPI_SUM, comm);
    }
    if (counts[1] > counts[0] / 10) {
      std::string culprits;
      std::vector<size_t> order(byLabel.size());
      for (size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(),
                       [&](size_t a, size_t b) { return byLabel[a] > byLabel[b]; });
      for (size_t k = 0; k < std::min<size_t>(order.size(), 5) && byLabel[order[k]] > 0; ++k) {
        culprits +=
            std::string(k == 0 ? " most hit: " : ", ") + "'" + patches.labelNames[order[k]] + "' " +
            std::to_string(static_cast<int>(std::lround(100.0 * byLabel[order[k]] / counts[1]))) +
            "%";
      }
      console.warn(std::to_string(100 * counts[1] / counts[0]) +
                   "% of the rays hit the back of a face: is the scene's winding right?" +
                   culprits);
    }
  }

  // 3b. Reciprocity and sparsification: symmetrise A_i F_ij = A_j F_ji and/or drop small F_ij,
  // then restore every row's sum (Lawson's least-squares correction).
  if (settings.reciprocity || settings.dropThreshold > 0) {
    solve::ScopedStage stage("Repair form factors");
    std::vector<double> area(owned.size());
    for (int64_t r = 0; r < owned.size(); ++r) area[r] = patches.area(owned.begin + r);
    solve::RepairReport repair;
    rows = solve::repairFormFactors(rows, area, {settings.reciprocity, settings.dropThreshold},
                                    repair, comm);
    endStage("repair");
    char line[400];
    std::snprintf(line, sizeof line,
                  "repair: reciprocity defect %.3g (max pair %.3g, %.0f%% one-sided) -> %.2g; "
                  "dropped %.1f%% of nonzeros (%.2g%% of the weight); change %.3g; closure "
                  "%.2g -> %.2g in %lld CG iterations; %lld -> %lld nonzeros (%.0f -> %.0f "
                  "bytes per patch); %.2f s",
                  repair.reciprocityDefect, repair.maxPairDefect, 100 * repair.oneSidedShare,
                  repair.defectAfter, 100 * repair.droppedNonzeroShare,
                  100 * repair.droppedWeightShare, repair.change, repair.closureBefore,
                  repair.closureAfter, static_cast<long long>(repair.iterations),
                  static_cast<long long>(repair.nonzerosBefore),
                  static_cast<long long>(repair.nonzerosAfter), repair.bytesPerPatchBefore,
                  repair.bytesPerPatchAfter, attributes.stageSeconds["repair"]);
    console.info(line);
    if (!repair.converged) {
      console.warn("the closure repair's CG did not converge: row sums are off by up to " +
                   std::to_string(repair.closureAfter));
    }
    if (repair.emptyRows > 0) {
      console.warn(std::to_string(repair.emptyRows) +
                   " rows lost every entry to --drop-threshold and cannot be closed: lower it");
    }
    if (repair.negativeKept > 0) {
      console.warn("the closure repair made " + std::to_string(repair.negativeKept) +
                   " form factors negative (" + std::to_string(repair.negativeClipped) +
                   " tiny ones clipped to 0): lower --drop-threshold");
    }
  }

  // 4. Solve (I − diag(ρ_c) F) B_c = E_c per channel.
  std::vector<Rgb> reflectance(patches.reflectance.begin() + owned.begin,
                               patches.reflectance.begin() + owned.end);
  std::vector<Rgb> emission(patches.emission.begin() + owned.begin,
                            patches.emission.begin() + owned.end);
  solve::Report report;
  LocalSolution solution;
  {
    solve::ScopedStage stage("Solve");
    solution = solve::solveRadiosity(rows, patchCount, reflectance, emission,
                                     {settings.solver, settings.rtol}, report);
    endStage("solve");
    char line[200];
    std::snprintf(line, sizeof line,
                  "solve: %s, %lld iterations over %d channels, relative residual %.3g, %.2f s",
                  settings.solver.c_str(), static_cast<long long>(report.iterations),
                  report.channelsSolved, report.residual, attributes.stageSeconds["solve"]);
    console.info(line);
  }

  // 5. Write the result, each rank its own slab.
  attributes.ranks = console.ranks();
  attributes.raysPerPatch = settings.raysPerPatch;
  attributes.seed = settings.seed;
  attributes.solver = settings.solver;
  attributes.iterations = report.iterations;
  attributes.residual = report.residual;
  attributes.converged = report.converged;
  attributes.scene = settings.scene;
  attributes.options = describeSettings(settings, maxArea, console.ranks());
  {
    solve::ScopedStage stage("Write result");
    // F goes to the file as it is, each rank its own rows.
    FormFactorOutput formFactors{rowSumHistogram, formfactor::rowSumBinEdges()};
    if (settings.saveFormFactors) formFactors.rows = &rows;
    writeResult(comm, settings.output, patches, solution, attributes, formFactors);
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
