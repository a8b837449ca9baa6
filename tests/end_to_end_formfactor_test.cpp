// Form factors as users get them from `radiosity solve`: the analytic view factor of the plates,
// the same patches and F on any number of ranks and at any scale, --patches and --mesh-only,
// saved rows of F and their row-sum histogram, and reciprocity with dropping. Exact rows and
// group factors: end_to_end_exact_rows_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "analytic_view_factors.h"
#include "core/matrix_rows.h"
#include "end_to_end_fixture.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::ProgramRun;

TEST_F(EndToEnd, PlatesMatchTheAnalyticViewFactor) {
  const int64_t rays = 256;
  std::string out = path("plates.h5");
  ProgramRun run = radiosity(
      2, "solve builtin:plates --max-area 0.005 --rays " + std::to_string(rays) + " -q -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(out);
  // With ρ = 0 the receiver's irradiance is its form factor to the emitter (E = 1).
  double weighted = 0, area = 0;
  int64_t receivers = 0;
  for (size_t i = 0; i < result.area.size(); ++i) {
    if (result.mesh.emission[i][0] > 0) continue;
    weighted += result.area[i] * result.irradiance[i][0];
    area += result.area[i];
    ++receivers;
  }
  const double exact = 0.19982, mean = weighted / area;
  const double sigma = std::sqrt(exact * (1 - exact) / (double(rays) * receivers));
  EXPECT_NEAR(mean, exact, 3 * sigma);
}

TEST_F(EndToEnd, PatchesOptionReachesTheCountWithTheSameIdsOnAnyRankCount) {
  const std::string options = " 'builtin:rooms?patches=2000' --patches 3000 --rays 16 -o ";
  ProgramRun two = radiosity(2, "solve" + options + path("two.h5"));
  ASSERT_EQ(two.exitCode, 0) << two.output;
  EXPECT_NE(two.output.find("--patches 3000: area bound"), std::string::npos) << two.output;
  ProgramRun one = radiosity(1, "solve" + options + path("one.h5"));
  ASSERT_EQ(one.exitCode, 0) << one.output;
  Result a = readResult(path("one.h5")), b = readResult(path("two.h5"));
  EXPECT_GE(b.mesh.triangleCount(), 2400);
  EXPECT_LE(b.mesh.triangleCount(), 3600);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_TRUE(b.attributes.converged);
  EXPECT_NE(b.attributes.options.find("patches = 3000"), std::string::npos);

  ProgramRun both =
      radiosity(1, "solve builtin:box --patches 100 --max-area 0.1 -o " + path("both.h5"));
  EXPECT_EQ(both.exitCode, 2) << both.output;
  EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
  EXPECT_FALSE(fs::exists(path("both.h5")));
}

TEST_F(EndToEnd, MeshOnlyStopsAfterMeshingAndWritesNothing) {
  ProgramRun run = radiosity(2, "solve builtin:cornell --mesh-only -o " + path("none.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("stage times (s): load"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("form factors:"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("none.h5")));
}

// --save-formfactors: every row of F comes from random numbers keyed by (seed, patch id, sample
// index), so the saved rows are the same bit for bit whichever rank computed them.
TEST_F(EndToEnd, SavedFormFactorsAreBitForBitTheSameOnOneTwoAndThreeRanks) {
  // (hemisphere sampling: closed rows sum to 1 exactly)
  const std::string options =
      " --max-area 4000 --rays 64 --estimator hemisphere --rtol 1e-10 --save-formfactors -q -o ";
  std::vector<Result> results;
  for (int ranks : {1, 2, 3}) {
    const std::string out = path("ranks" + std::to_string(ranks) + ".h5");
    ProgramRun run = radiosity(ranks, "solve builtin:cornell" + options + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.push_back(readResult(out));
  }
  const Result& one = results[0];
  ASSERT_TRUE(one.formFactors.has_value());
  const SparseRows& f = *one.formFactors;
  const int64_t np = one.mesh.triangleCount();
  ASSERT_EQ(f.rowCount(), np);
  ASSERT_GT(f.nonzeros(), np);
  // Each row: columns ascending, never the patch itself, values in (0, 1] summing to at most 1.
  for (int64_t i = 0; i < np; ++i) {
    double sum = 0;
    for (int64_t k = f.rowStart[i]; k < f.rowStart[i + 1]; ++k) {
      ASSERT_NE(f.column[k], i);
      if (k > f.rowStart[i]) {
        ASSERT_LT(f.column[k - 1], f.column[k]) << "row " << i;
      }
      ASSERT_GT(f.value[k], 0);
      sum += f.value[k];
    }
    ASSERT_LE(sum, 1 + 1e-12) << "row " << i;
  }
  for (size_t r = 1; r < results.size(); ++r) {
    ASSERT_TRUE(results[r].formFactors.has_value()) << r + 1 << " ranks";
    EXPECT_EQ(results[r].formFactors->rowStart, f.rowStart) << r + 1 << " ranks";
    EXPECT_EQ(results[r].formFactors->column, f.column) << r + 1 << " ranks";
    EXPECT_EQ(results[r].formFactors->value, f.value) << r + 1 << " ranks";  // exact
    EXPECT_EQ(results[r].rowSumHistogram, one.rowSumHistogram) << r + 1 << " ranks";
  }
  EXPECT_NE(std::find(results[2].rank.begin(), results[2].rank.end(), 2), results[2].rank.end());
  // The row-sum histogram is always there and counts every patch once.
  ASSERT_FALSE(one.rowSumHistogram.empty());
  EXPECT_GE(one.rowSumBinEdges.size(), one.rowSumHistogram.size());
  int64_t counted = 0;
  for (int64_t count : one.rowSumHistogram) counted += count;
  EXPECT_EQ(counted, np);
  // `info` lists the new datasets and still summarises the result.
  ProgramRun info = radiosity(1, "info " + path("ranks3.h5"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  for (const char* name : {"/formfactors/row_start", "/formfactors/column", "/formfactors/value",
                           "/formfactors/row_sum_histogram", "summary:"})
    EXPECT_NE(info.output.find(name), std::string::npos) << name << "\n" << info.output;
}

// --save-formfactors writes F from its one store, as the solve gives it back, a piece of 2^21
// nonzeros at a time (no copy of F for the file); a solver that changes M in place (gauss-seidel)
// keeps a copy for the file instead. The Cornell box at 1024 samples has ~4·10^6 nonzeros: two
// pieces on one rank, one on each of two. Every way gives the same /formfactors bit for bit. (The
// default stores F in single precision; gauss-seidel alone would store it in double, so it is
// asked for single: its copy is then of the same rounded values.)
TEST_F(EndToEnd, FormFactorsWrittenFromTheStoreInPiecesEqualTheCopy) {
  const std::string options = " builtin:cornell --refine-rounds 0 --save-formfactors -q -o ";
  std::vector<Result> results;
  ASSERT_NO_FATAL_FAILURE(solveOnEach({{1, 1}, {2, 1}}, options, results));
  const ProgramRun copied = radiosity(
      1, "solve --solver gauss-seidel --formfactor-precision single" + options + path("gs.h5"));
  ASSERT_EQ(copied.exitCode, 0) << copied.output;
  results.push_back(readResult(path("gs.h5")));
  const Result& one = results[0];
  ASSERT_TRUE(one.formFactors.has_value());
  ASSERT_GT(one.formFactors->nonzeros(), int64_t{1} << 21);  // more than one piece on one rank
  ASSERT_EQ(one.formFactors->rowCount(), one.mesh.triangleCount());
  for (size_t r = 1; r < results.size(); ++r) {
    SCOPED_TRACE(r == 1 ? "2 ranks" : "gauss-seidel");
    ASSERT_TRUE(results[r].formFactors.has_value());
    EXPECT_EQ(results[r].formFactors->rowStart, one.formFactors->rowStart);
    EXPECT_EQ(results[r].formFactors->column, one.formFactors->column);
    EXPECT_EQ(results[r].formFactors->value, one.formFactors->value);  // exact
  }
}

// Blocks cut by measured cost (--balance cost; auto from 4 ranks) move rows between ranks and never
// change them: F is the same bit for bit as on one rank, B the same up to solver round-off. The
// default Cornell box (~5800 patches) at 64 samples is long enough for the pilot to run. With
// --balance count the blocks are those of equal counts.
// MIS in a scene of several lights (3 rooms): each cluster's light choice comes from a pilot
// keyed by the seed and the cluster's patches, so F is the same bit for bit on 1, 2 and 3 ranks
// and on 2 threads, and B up to the solver's round-off.
TEST_F(EndToEnd, LightChoiceGivesTheSameFormFactorsOnAnyRankAndThreadCount) {
  std::vector<Result> results;
  ASSERT_NO_FATAL_FAILURE(solveOnEach({{1, 1}, {2, 1}, {3, 1}, {1, 2}},
                                      " 'builtin:rooms?patches=6000' --rays 16 --estimator mis"
                                      " --rtol 1e-10 --save-formfactors -q -o ",
                                      results));
  const Result& one = results[0];
  ASSERT_TRUE(one.formFactors.has_value());
  for (size_t r = 1; r < results.size(); ++r) {
    SCOPED_TRACE("run " + std::to_string(r));
    ASSERT_TRUE(results[r].formFactors.has_value());
    EXPECT_EQ(results[r].formFactors->column, one.formFactors->column);
    EXPECT_EQ(results[r].formFactors->value, one.formFactors->value);  // exact
    for (size_t i = 0; i < one.radiosity.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(results[r].radiosity[i][c], one.radiosity[i][c],
                    1e-7 * one.radiosity[i][c] + 1e-12)
            << "patch " << i;
  }
}

TEST_F(EndToEnd, BlocksCutByMeasuredCostGiveTheSameFormFactorsAsOneRank) {
  const std::string options =
      " --rays 64 --estimator hemisphere --rtol 1e-10 --save-formfactors -o ";
  std::vector<Result> results;
  for (int ranks : {1, 2, 3}) {
    const std::string out = path("ranks" + std::to_string(ranks) + ".h5");
    ProgramRun run = radiosity(ranks, "solve builtin:cornell --balance cost" + options + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    if (ranks > 1) {
      EXPECT_NE(run.output.find("balance: blocks by measured cost"), std::string::npos)
          << run.output;
      EXPECT_NE(run.output.find("balance: per rank, form-factor CPU time max/mean"),
                std::string::npos)
          << run.output;
    }
    results.push_back(readResult(out));
  }
  const Result& one = results[0];
  ASSERT_TRUE(one.formFactors.has_value());
  const int64_t np = one.mesh.triangleCount();
  bool someBlockNotByCount = false;
  for (size_t r = 1; r < results.size(); ++r) {
    const int ranks = static_cast<int>(r) + 1;
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const Result& many = results[r];
    ASSERT_TRUE(many.formFactors.has_value());
    EXPECT_EQ(many.formFactors->rowStart, one.formFactors->rowStart);
    EXPECT_EQ(many.formFactors->column, one.formFactors->column);
    EXPECT_EQ(many.formFactors->value, one.formFactors->value);  // exact
    ASSERT_EQ(many.radiosity.size(), one.radiosity.size());
    for (size_t i = 0; i < one.radiosity.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(many.radiosity[i][c], one.radiosity[i][c], 1e-7 * one.radiosity[i][c] + 1e-12)
            << "patch " << i;
    // Contiguous blocks in rank order, every rank holding some.
    ASSERT_EQ(static_cast<int64_t>(many.rank.size()), np);
    EXPECT_TRUE(std::is_sorted(many.rank.begin(), many.rank.end()));
    EXPECT_EQ(many.rank.front(), 0);
    EXPECT_EQ(many.rank.back(), ranks - 1);
    for (int r = 0; r < ranks; ++r) {
      const auto size = std::count(many.rank.begin(), many.rank.end(), r);
      if (size != np / ranks + (r < np % ranks ? 1 : 0)) someBlockNotByCount = true;
    }
  }
  EXPECT_TRUE(someBlockNotByCount) << "the blocks were cut by count on 2 and on 3 ranks";

  const std::string counted = path("count.h5");
  ProgramRun run = radiosity(3, "solve builtin:cornell --balance count" + options + counted);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("balance: blocks by count (--balance count)"), std::string::npos)
      << run.output;
  const Result byCount = readResult(counted);
  EXPECT_EQ(byCount.formFactors->value, one.formFactors->value);
  for (int r = 0, id = 0; r < 3; ++r) {
    const int64_t size = np / 3 + (r < np % 3 ? 1 : 0);
    for (int64_t k = 0; k < size; ++k, ++id) ASSERT_EQ(byCount.rank[id], r) << "patch " << id;
  }

  // The default, auto: by count on 2 ranks (the pilot would cost what it saves), by cost on 4.
  ProgramRun two = radiosity(2, "solve builtin:cornell" + options + path("auto2.h5"));
  ASSERT_EQ(two.exitCode, 0) << two.output;
  EXPECT_NE(two.output.find("balance: blocks by count (2 ranks (--balance auto"), std::string::npos)
      << two.output;
  ProgramRun four = radiosity(4, "solve builtin:cornell" + options + path("auto4.h5"));
  ASSERT_EQ(four.exitCode, 0) << four.output;
  EXPECT_NE(four.output.find("balance: blocks by measured cost"), std::string::npos) << four.output;
  EXPECT_EQ(readResult(path("auto4.h5")).formFactors->value, one.formFactors->value);
}

// Without --save-formfactors only the histogram is written; in a closed box every row sums to 1,
// so every patch is counted in the bin that holds 1.
TEST_F(EndToEnd, RowSumHistogramCountsEveryPatchOnce) {
  const std::string out = path("box.h5");
  ProgramRun run = radiosity(2, "solve builtin:box --max-area 0.02 --rays 64 -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("row sums of F"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("bytes per patch"), std::string::npos) << run.output;
  // Where memory grows: the peak by the end of each stage, never falling from stage to stage.
  const size_t memory = run.output.find("memory: peak resident set");
  ASSERT_NE(memory, std::string::npos) << run.output;
  std::istringstream line(run.output.substr(run.output.find("(MB):", memory) + 5));
  double previous = 0;
  for (const char* stage : {"load", "mesh", "formfactors", "solve", "write"}) {
    std::string name;
    double megabytes = -1;
    line >> name >> megabytes;
    EXPECT_EQ(name, stage);
    EXPECT_GT(megabytes, 1.0) << stage;
    EXPECT_GE(megabytes, previous) << stage;
    previous = megabytes;
  }
  const Result result = readResult(out);
  EXPECT_FALSE(result.formFactors.has_value());
  ASSERT_FALSE(result.rowSumHistogram.empty());
  ASSERT_GE(result.rowSumBinEdges.size(), result.rowSumHistogram.size());
  size_t one = 0;  // the last bin whose lower edge is at most 1
  while (one + 1 < result.rowSumHistogram.size() && result.rowSumBinEdges[one + 1] <= 1) ++one;
  int64_t counted = 0;
  for (int64_t count : result.rowSumHistogram) counted += count;
  EXPECT_EQ(counted, result.mesh.triangleCount());
  EXPECT_EQ(result.rowSumHistogram[one], result.mesh.triangleCount());
}

double worstRelativeGap(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  double worst = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(a[i][c] - b[i][c]) / std::max(std::abs(a[i][c]), 1e-300));
  return worst;
}

// Sampling is scale-free: points and directions do not depend on the size, and the ray offset
// is a fixed share of the scene's diagonal. Scaling by a power of two is exact in double and in
// Embree's float, so a box and the Cornell box at scales 2^-13, 1 and 2^13 give the same patches,
// form factors and radiosity bit for bit.
TEST_F(EndToEnd, ScenesScaledByPowersOfTwoGiveTheSameFormFactorsBitForBit) {
  for (const char* scene : {"builtin:box?size=", "builtin:cornell?scale="}) {
    std::vector<Result> results;
    for (const char* scale : {"0.0001220703125", "1", "8192"}) {  // 2^-13, 1, 2^13
      const std::string out = path(std::string("scaled") + scale + ".h5");
      ProgramRun run =
          radiosity(2, "solve '" + std::string(scene) + scale +
                           "' --patches 1000 --rays 64 --save-formfactors -q -o " + out);
      ASSERT_EQ(run.exitCode, 0) << run.output;
      results.push_back(readResult(out));
    }
    const Result& unit = results[1];
    ASSERT_TRUE(unit.formFactors.has_value());
    for (const Result& scaled : results) {
      ASSERT_EQ(scaled.mesh.triangles, unit.mesh.triangles) << scene;
      // E is exitance, the same at any scale, and so is B.
      EXPECT_LT(worstRelativeGap(scaled.radiosity, unit.radiosity), 1e-12) << scene;
      ASSERT_TRUE(scaled.formFactors.has_value());
      EXPECT_EQ(scaled.formFactors->rowStart, unit.formFactors->rowStart) << scene;
      EXPECT_EQ(scaled.formFactors->column, unit.formFactors->column) << scene;
      EXPECT_EQ(scaled.formFactors->value, unit.formFactors->value) << scene;
    }
  }
}

// Sizes 1e-4, 1 and 1e4 (area bound scaled with them, so the patches are the same). These scales
// round: a vertex at 1e-4·x is not exactly 1e-4 times the vertex at x, in double or in Embree's
// float, so a ray that grazes the edge between two patches may land on the other one. The form
// factors are therefore the same only up to such rays (checked: nearly every row bit for bit, the
// others off by a ray or two), while closure holds exactly and B = E/(1 − ρ) at every scale.
TEST_F(EndToEnd, ClosedBoxIsTheSameAtDecimalScales) {
  const int64_t rays = 64;
  std::vector<Result> results;
  for (const auto& [size, maxArea] : std::vector<std::pair<std::string, std::string>>{
           {"1e-4", "5e-11"}, {"1", "0.005"}, {"1e4", "5e5"}}) {
    const std::string out = path("box" + size + ".h5");
    ProgramRun run =
        radiosity(2, "solve 'builtin:box?size=" + size + "' --max-area " + maxArea + " --rays " +
                         std::to_string(rays) + " --save-formfactors -q -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.push_back(readResult(out));
  }
  const Result& unit = results[1];
  ASSERT_TRUE(unit.formFactors.has_value());
  const SparseRows& f = *unit.formFactors;
  const int64_t np = unit.mesh.triangleCount();
  for (const Result& scaled : results) {
    ASSERT_EQ(scaled.mesh.triangles, unit.mesh.triangles);
    EXPECT_LT(worstRelativeGap(scaled.radiosity, unit.radiosity), 1e-9);
    for (const Rgb& b : scaled.radiosity) ASSERT_NEAR(b[0], 2.0, 1e-8);  // E = 1, ρ = 0.5
    ASSERT_TRUE(scaled.formFactors.has_value());
    const SparseRows& g = *scaled.formFactors;
    ASSERT_EQ(g.rowCount(), np);
    int64_t rowsDiffering = 0;
    for (int64_t i = 0; i < np; ++i) {
      double sum = 0;
      std::map<int64_t, double> gap;  // column -> F_ij of this scale minus F_ij at size 1
      for (int64_t k = g.rowStart[i]; k < g.rowStart[i + 1]; ++k) {
        sum += g.value[k];
        gap[g.column[k]] += g.value[k];
      }
      for (int64_t k = f.rowStart[i]; k < f.rowStart[i + 1]; ++k) gap[f.column[k]] -= f.value[k];
      ASSERT_NEAR(sum, 1.0, 1e-12) << "row " << i;  // closed: every ray hits a front face
      double moved = 0;
      for (const auto& [j, d] : gap) moved += std::abs(d);
      if (moved > 0) ++rowsDiffering;
      EXPECT_LE(moved, 4.0 / rays + 1e-12) << "row " << i << ": more than two rays moved";
    }
    EXPECT_LE(rowsDiffering, np / 100) << "rows whose form factors differ from size 1";
  }
}

// The Cornell box from 1e-30 to 1e25 (its coordinates reach 5.6e27; beyond 1e30 scenes are
// refused): the same patches (refinement ties are broken with a relative tolerance) and the
// same B up to the few rays that graze an edge. Tracing happens in the scene's own frame
// (TracingFrame), so Embree's float arithmetic never sees 1e18 (where every ray used to escape)
// or 1e-25.
TEST_F(EndToEnd, CornellBoxGivesTheSameAnswerAtEveryScale) {
  const std::vector<const char*> scales = {"1e-30", "1e-20", "1e-4", "1", "1e4", "1e18", "1e25"};
  std::vector<Result> results;
  for (const char* scale : scales) {
    const std::string out = path(std::string("cornell") + scale + ".h5");
    ProgramRun run = radiosity(
        2, "solve 'builtin:cornell?scale=" + std::string(scale) + "' --rays 64 -q -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.push_back(readResult(out));
  }
  const Result& unit = results[3];
  double largest = 0;
  for (const Rgb& b : unit.radiosity) largest = std::max({largest, b[0], b[1], b[2]});
  for (size_t k = 0; k < results.size(); ++k) {
    const Result& scaled = results[k];
    ASSERT_EQ(scaled.mesh.triangles, unit.mesh.triangles) << scales[k];
    ASSERT_EQ(scaled.mesh.sourceFace, unit.mesh.sourceFace) << scales[k];
    double gap = 0;
    for (size_t i = 0; i < unit.radiosity.size(); ++i)
      for (int c = 0; c < 3; ++c)
        gap = std::max(gap, std::abs(scaled.radiosity[i][c] - unit.radiosity[i][c]));
    EXPECT_LE(gap / largest, 1e-4) << scales[k];
    // The result keeps the user's coordinates.
    EXPECT_NEAR(scaled.mesh.vertices[0].x, std::stod(scales[k]) * unit.mesh.vertices[0].x,
                1e-12 * std::abs(std::stod(scales[k]) * unit.mesh.vertices[0].x));
  }
  // A camera too far to trace from is refused (exit 2), not an Embree abort.
  ProgramRun far =
      radiosity(1, "render " + path("cornell1.h5") + " --eye 0.5,0.5,1e20 -o " + path("far.png"));
  EXPECT_EQ(far.exitCode, 2) << far.output;
  EXPECT_NE(far.output.find("too far to trace"), std::string::npos) << far.output;
  EXPECT_FALSE(fs::exists(path("far.png")));
  ProgramRun tiny = radiosity(1, "render " + path("cornell1e-30.h5") + " -o " + path("tiny.png"));
  EXPECT_EQ(tiny.exitCode, 0) << tiny.output;
}

// Reciprocity with dropping and the closure repair: the rows of the closed box sum to 1 again,
// so B = E/(1 − ρ) holds exactly, however noisy and sparse F is.
TEST_F(EndToEnd, ReciprocityAndDroppingKeepTheClosedBoxExact) {
  for (const char* threshold : {"0.001", "0.02"}) {  // 64 rays: 0.02 drops every single hit
    std::string out = path("box.h5");
    // (Sampled rows: exact ones, thousands per row, would all be below the thresholds.)
    ProgramRun run = radiosity(2, std::string("solve 'builtin:box?rho=0.9' --reciprocity ") +
                                      "--exact-rows off " + "--drop-threshold " + threshold +
                                      " --max-area 0.02 --rays 64 -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_NE(run.output.find("repair: reciprocity defect"), std::string::npos) << run.output;
    Result result = readResult(out);
    ASSERT_GT(result.radiosity.size(), 300u);
    for (const Rgb& b : result.radiosity) {
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(b[c], 10.0, 1e-6 * 10.0) << threshold;
    }
    EXPECT_NE(result.attributes.options.find("reciprocity = true"), std::string::npos);
    EXPECT_NE(result.attributes.options.find(std::string("drop-threshold = ") + threshold),
              std::string::npos)
        << result.attributes.options;
  }
}

}  // namespace
}  // namespace radiosity
