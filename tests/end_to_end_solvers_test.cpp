// The solvers as users run them (`mpiexec -n R radiosity solve ...`): B = E/(1 − ρ) in closed
// boxes up to ρ = 0.9999, plain failures where a solver cannot, no work a grey or black scene
// does not need, and the same answer from every solver and on 1, 2 and 3 ranks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "core/matrix_rows.h"
#include "end_to_end_fixture.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::figure;
using testing::ProgramRun;
using testing::writeBox;

class ClosedBox
    : public EndToEnd,
      public ::testing::WithParamInterface<std::tuple<double, std::string, std::string>> {};

// Stiff systems: the Krylov solvers reach B = E/(1 − ρ) up to ρ = 0.9999, with rows sampled
// (every ray hits: they sum to 1) and exact (scaled to 1 where the patches close the scene).
TEST_P(ClosedBox, RadiosityIsEmissionOverOneMinusReflectance) {
  const auto& [rho, solver, rows] = GetParam();
  std::string out = path("box.h5");
  ProgramRun run = radiosity(2, "solve 'builtin:box?rho=" + std::to_string(rho) +
                                    "&e=1' --max-area 0.02 --rays 64 -q --rtol 1e-10 --solver " +
                                    solver + " --exact-rows " + rows + " -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(out);
  const double exact = 1.0 / (1.0 - rho);
  ASSERT_GT(result.radiosity.size(), 300u);
  for (const Rgb& b : result.radiosity) {
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(b[c], exact, 1e-6 * exact);
  }
  EXPECT_EQ(result.attributes.ranks, 2);
  EXPECT_EQ(result.attributes.solver, solver);
  EXPECT_TRUE(result.attributes.converged);
  EXPECT_LE(result.attributes.residual, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Reflectances, ClosedBox,
                         ::testing::Combine(::testing::Values(0.5, 0.9, 0.99, 0.999, 0.9999),
                                            ::testing::Values("gmres", "cg"),
                                            ::testing::Values("auto", "off")));

// Every surface of a closed cube of 20 × 20 squares a face emits (E = 1, ρ = 0.5), so
// B = 2 exactly and its only sampling error is the rare ray a run loses (a back face at an edge):
// the row sum of that patch falls by 1/N. The estimated error must follow the measured one at
// both ray counts, not a floor of round-off: where no ray is lost (seed 3 here), B is exact to
// round-off and so must the estimate be (before the calibration summed its variances without
// cancellation and compared the gathers' spread with the model of their own rows, it scaled
// round-off up: 3e-9 here at 1,024 rays, 2.8e-4 against 1.1e-6 measured on 40 × 40 squares at
// 16,384; docs/notebook/accuracy-measurements.md).
TEST_F(EndToEnd, EstimatedErrorOfAnEmittingClosedCubeFollowsTheMeasuredOne) {
  const int n = 20;
  std::ofstream mtl(path("cube.mtl"));
  mtl << "newmtl wall\nKd 0.5 0.5 0.5\nKe 1 1 1\n";
  mtl.close();
  std::ofstream obj(path("cube.obj"));
  obj << "mtllib cube.mtl\nusemtl wall\n";
  int vertices = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          int corner[4];
          const int steps[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
          for (int k = 0; k < 4; ++k) {
            double p[3];
            p[axis] = side;
            p[u] = static_cast<double>(a + steps[k][0]) / n;
            p[v] = static_cast<double>(b + steps[k][1]) / n;
            obj << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
            corner[k] = ++vertices;
          }
          // normals inward: +axis on side 0, −axis on side 1
          if (side == 0)
            obj << "f " << corner[0] << ' ' << corner[1] << ' ' << corner[2] << ' ' << corner[3];
          else
            obj << "f " << corner[3] << ' ' << corner[2] << ' ' << corner[1] << ' ' << corner[0];
          obj << '\n';
        }
      }
    }
  }
  obj.close();
  for (int rays : {1024, 4096}) {
    const std::string out = path("cube" + std::to_string(rays) + ".h5");
    ProgramRun run = radiosity(2, "solve " + path("cube.obj") + " --max-area 1e9 --exact-rows off" +
                                      " --seed 3 -q --rays " + std::to_string(rays) + " -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    Result result = readResult(out);
    ASSERT_EQ(result.radiosity.size(), 6u * 2 * n * n);
    double squares = 0, area = 0;
    for (size_t i = 0; i < result.radiosity.size(); ++i) {
      const double a = result.area[i], error = (result.radiosity[i][0] - 2.0) / 2.0;
      squares += a * error * error, area += a;
    }
    const double measured = std::sqrt(squares / area);
    const double estimate = figure(result, "error_estimate");
    // (below 1e-9 both are round-off and rare rays: nothing to compare)
    EXPECT_LE(estimate, std::max(1.5 * measured, 1e-9)) << rays << " rays; measured " << measured;
    if (measured > 1e-8) {
      EXPECT_GE(estimate, measured / 1.5) << rays << " rays; measured " << measured;
    }
    std::printf("%d rays: estimate %.3g, measured %.3g\n", rays, estimate, measured);
  }
}

class StiffBox : public EndToEnd,
                 public ::testing::WithParamInterface<std::tuple<double, std::string>> {};

// Uniform E is an eigenvector of F in a closed box, so the test above is one step for a Krylov
// method. Light from one face is not: it must bounce about 1/(1 − ρ) times. With a reciprocal F
// whose rows sum to 1 (hemisphere sampling) the power balances exactly: Σ A_i B_i =
// Σ A_i E_i / (1 − ρ).
TEST_P(StiffBox, OneEmittingFaceBalancesThePowerExactly) {
  const auto& [rho, solver] = GetParam();
  std::vector<Rgb> emission(6, {0, 0, 0});
  emission[2] = {1, 1, 1};
  writeBox(path("box.obj"), std::vector<Rgb>(6, {rho, rho, rho}), emission);
  ProgramRun run = radiosity(2, "solve " + path("box.obj") +
                                    " --max-area 0.01 --rays 32 --reciprocity -q --rtol 1e-10 "
                                    "--estimator hemisphere --solver " +
                                    solver + " -o " + path("box.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(path("box.h5"));
  double reflected = 0, emitted = 0;
  for (size_t i = 0; i < result.area.size(); ++i) {
    reflected += result.area[i] * result.radiosity[i][0];
    emitted += result.area[i] * result.mesh.emission[i][0];
  }
  EXPECT_NEAR(reflected / (emitted / (1 - rho)), 1.0, 1e-6);
  EXPECT_GT(result.attributes.iterations, 3);  // a real iteration, not one step
}

INSTANTIATE_TEST_SUITE_P(Reflectances, StiffBox,
                         ::testing::Combine(::testing::Values(0.9, 0.99, 0.999, 0.9999),
                                            ::testing::Values("gmres", "cg")));

// Jacobi needs about 1/(1 − ρ) sweeps: at ρ = 0.9999 it meets its cap and says what to use.
TEST_F(EndToEnd, JacobiAtItsIterationCapFailsNamingTheOptionToUse) {
  std::string out = path("box.h5");
  ProgramRun run = radiosity(
      2, "solve 'builtin:box?rho=0.9999' --max-area 0.05 --rays 16 -q --solver jacobi -o " + out);
  EXPECT_EQ(run.exitCode, 4) << run.output;
  EXPECT_NE(run.output.find("did not converge"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--solver gmres"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("-ksp_max_it"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
}

// An emission so large that B overflows: the run stops instead of writing Inf.
// An emission whose B would overflow the solver's norms (they square B) is refused before the
// work (it used to end in exit 4, "iterate is not finite", after it).
TEST_F(EndToEnd, AnEmissionThatWouldOverflowIsRefusedBeforeTheWork) {
  std::string out = path("box.h5");
  ProgramRun run =
      radiosity(2, "solve 'builtin:box?rho=0.99&e=1e307' --max-area 0.05 --rays 16 -q -o " + out);
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("1e100"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
}

class ExtremeEmission : public EndToEnd, public ::testing::WithParamInterface<std::string> {};

TEST_P(ExtremeEmission, GivesTheSameRelativeAnswerWithoutUnderOrOverflow) {
  const double e = std::stod(GetParam()), rho = 0.9;
  std::string out = path("extreme.h5");
  ProgramRun run = radiosity(
      2, "solve 'builtin:box?rho=0.9&e=" + GetParam() + "' --max-area 0.05 --rays 16 -q -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  for (const Rgb& b : readResult(out).radiosity) {
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(b[c] / (e / (1 - rho)), 1.0, 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(Emissions, ExtremeEmission, ::testing::Values("1e-30", "1e30"));

TEST_F(EndToEnd, AClosedSceneThatReflectsEverythingIsRefusedAsSingular) {
  std::string out = path("white.h5");
  ProgramRun run = radiosity(2, "solve 'builtin:box?rho=1' --max-area 0.05 --rays 16 -q -o " + out);
  EXPECT_EQ(run.exitCode, 4) << run.output;
  EXPECT_NE(run.output.find("singular"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
}

// The solve line says how many channels were solved: "... over N channels solved ...".
int channelsSolved(const std::string& output) {
  const std::string key = " iterations over ";
  size_t at = output.find(key);
  return at == std::string::npos ? -1 : std::stoi(output.substr(at + key.size()));
}

TEST_F(EndToEnd, WorkAGreyOrNonReflectingSceneDoesNotNeedIsLeftOut) {
  // Grey: one solve for three channels.
  ProgramRun grey =
      radiosity(2, "solve 'builtin:box?rho=0.7' --max-area 0.05 --rays 16 -o " + path("grey.h5"));
  ASSERT_EQ(grey.exitCode, 0) << grey.output;
  EXPECT_EQ(channelsSolved(grey.output), 1) << grey.output;
  EXPECT_EQ(readResult(path("grey.h5")).attributes.leftOut,
            "green: same reflectance and emission as red; blue: same reflectance and emission as "
            "red");
  // No reflection anywhere: no solve at all, B = E.
  ProgramRun plates =
      radiosity(2, "solve builtin:plates --max-area 0.05 --rays 16 -o " + path("plates.h5"));
  ASSERT_EQ(plates.exitCode, 0) << plates.output;
  EXPECT_EQ(channelsSolved(plates.output), 0) << plates.output;
  Result result = readResult(path("plates.h5"));
  EXPECT_EQ(result.attributes.iterations, 0);
  EXPECT_NE(result.attributes.leftOut.find("blue: no reflection, B = E"), std::string::npos);
  EXPECT_EQ(result.radiosity, result.mesh.emission);
  // Coloured: every channel solved, nothing left out.
  ProgramRun cornell =
      radiosity(2, "solve builtin:cornell --max-area 8000 --rays 16 -o " + path("cornell.h5"));
  ASSERT_EQ(cornell.exitCode, 0) << cornell.output;
  EXPECT_EQ(channelsSolved(cornell.output), 3) << cornell.output;
  EXPECT_EQ(readResult(path("cornell.h5")).attributes.leftOut, "none");
}

// Our PETSc option is read like PETSc's own: a value that is not a truth value is refused, with
// PETSc's message, and leaves no result; true and false both solve.
TEST_F(EndToEnd, ChannelsTogetherOptionRefusesAValueThatIsNotATruthValue) {
  const std::string solve = "solve builtin:cornell --rays 16 -o ";
  ProgramRun bad = radiosity(2, solve + path("bad.h5") + " -solve_channels_together maybe");
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.output.find("Unknown logical value: maybe"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(path("bad.h5")));
  for (const char* value : {"true", "false"}) {
    ProgramRun good = radiosity(
        2, solve + path(std::string(value) + ".h5") + " -solve_channels_together " + value);
    EXPECT_EQ(good.exitCode, 0) << good.output;
  }
}

// Solve work is counted, not timed: the grey box needs a third of the coloured one's entry
// products (the coloured one's three channels share their passes over F: fewer passes, but
// each multiplies every entry three times).
TEST_F(EndToEnd, AGreySceneIsSolvedOnceNotThreeTimes) {
  const std::vector<Rgb> emission{{1, 1, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const std::string options = " --max-area 0.01 --rays 32 -q --solver gmres -o ";
  writeBox(path("grey.obj"), std::vector<Rgb>(6, {0.7, 0.7, 0.7}), emission);
  writeBox(path("tinted.obj"), std::vector<Rgb>(6, {0.7, 0.69, 0.71}), emission);
  ASSERT_EQ(radiosity(2, "solve " + path("grey.obj") + options + path("grey.h5")).exitCode, 0);
  ASSERT_EQ(radiosity(2, "solve " + path("tinted.obj") + options + path("tinted.h5")).exitCode, 0);
  Result grey = readResult(path("grey.h5")), tinted = readResult(path("tinted.h5"));
  EXPECT_EQ(figure(grey, "channels_solved"), 1);
  EXPECT_EQ(figure(tinted, "channels_solved"), 3);
  EXPECT_EQ(figure(grey, "unknowns") * 3, figure(tinted, "unknowns"));
  EXPECT_LT(figure(grey, "matrix_products"), figure(tinted, "matrix_products"));
  EXPECT_LT(figure(grey, "nonzero_products"), 0.5 * figure(tinted, "nonzero_products"));
}

// Black patches (ρ = 0 in a channel) keep B = E and take no part in that channel's
// iteration; the answer still solves the whole system (checked with the saved F).
TEST_F(EndToEnd, BlackPatchesAreLeftOutOfTheIterationAndTheAnswerStillHolds) {
  // Face 1 emits and is black in every channel; face 0 is black in red only.
  std::vector<Rgb> rho(6, {0.8, 0.6, 0.6}), emission(6, {0, 0, 0});
  rho[1] = {0, 0, 0};
  rho[0] = {0, 0.6, 0.6};
  emission[1] = {1, 2, 2};
  const std::string options =
      " --max-area 0.01 --rays 32 -q --rtol 1e-10 --solver gmres --save-formfactors -o ";
  writeBox(path("black.obj"), rho, emission);
  ProgramRun run = radiosity(2, "solve " + path("black.obj") + options + path("black.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(path("black.h5"));
  const int64_t np = result.mesh.triangleCount(), perFace = np / 6;
  EXPECT_NE(result.attributes.leftOut.find("red: " + std::to_string(2 * perFace) +
                                           " black patches (rho = 0) outside the iteration"),
            std::string::npos)
      << result.attributes.leftOut;
  EXPECT_NE(result.attributes.leftOut.find("green: " + std::to_string(perFace) + " black patches"),
            std::string::npos)
      << result.attributes.leftOut;
  EXPECT_NE(result.attributes.leftOut.find("blue: same reflectance and emission as green"),
            std::string::npos);
  EXPECT_EQ(figure(result, "unknowns"), (np - 2 * perFace) + (np - perFace));

  // The same box with the black faces grey iterates on every patch: more work.
  std::vector<Rgb> greyRho = rho;
  greyRho[0] = greyRho[1] = {0.8, 0.6, 0.6};
  writeBox(path("grey.obj"), greyRho, emission);
  ASSERT_EQ(radiosity(2, "solve " + path("grey.obj") + options + path("grey.h5")).exitCode, 0);
  Result grey = readResult(path("grey.h5"));
  EXPECT_EQ(figure(grey, "unknowns"), 2 * np);
  EXPECT_LT(figure(result, "nonzero_products"), figure(grey, "nonzero_products"));

  // B = E on black patches, and E − B + ρ F B = 0 everywhere, to the solver's tolerance.
  ASSERT_TRUE(result.formFactors.has_value());
  const SparseRows& f = *result.formFactors;
  for (int c = 0; c < 3; ++c) {
    double residual = 0, emitted = 0;
    for (int64_t i = 0; i < np; ++i) {
      const double rhoIc = result.mesh.reflectance[i][c];
      if (rhoIc == 0) {
        ASSERT_EQ(result.radiosity[i][c], result.mesh.emission[i][c]);
      }
      double gathered = 0;
      for (int64_t k = f.rowStart[i]; k < f.rowStart[i + 1]; ++k)
        gathered += f.value[k] * result.radiosity[f.column[k]][c];
      const double r = result.mesh.emission[i][c] - result.radiosity[i][c] + rhoIc * gathered;
      residual += r * r;
      emitted += result.mesh.emission[i][c] * result.mesh.emission[i][c];
    }
    EXPECT_LE(std::sqrt(residual / emitted), 1e-9) << "channel " << c;
  }
}

// Every solver reaches the same B on the Cornell box (the same reciprocal F for all), and each
// stores its history, its error bound and its condition estimate.
TEST_F(EndToEnd, EverySolverReachesTheSameAnswerOnTheCornellBox) {
  const std::string options = " --max-area 8000 --rays 64 --reciprocity -q --rtol 1e-10 ";
  std::map<std::string, Result> results;
  for (const char* solver : {"gmres", "jacobi", "gauss-seidel", "cg", "chebyshev", "southwell"}) {
    const std::string out = path(std::string(solver) + ".h5");
    ProgramRun run =
        radiosity(2, "solve builtin:cornell" + options + "--solver " + solver + " -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.emplace(solver, readResult(out));
  }
  const Result& reference = results.at("gmres");
  double largest = 0;
  for (const Rgb& b : reference.radiosity) largest = std::max({largest, b[0], b[1], b[2]});
  for (const auto& [solver, result] : results) {
    EXPECT_EQ(result.attributes.solver, solver);
    EXPECT_LE(result.attributes.residual, 1e-10) << solver;
    double gap = 0;
    for (size_t i = 0; i < result.radiosity.size(); ++i)
      for (int c = 0; c < 3; ++c)
        gap = std::max(gap, std::abs(result.radiosity[i][c] - reference.radiosity[i][c]));
    // Both within ~1e-10 of B*: the condition number is about 3 here.
    EXPECT_LE(gap / largest, 1e-8) << solver;
    const double bound = figure(result, "error_bound");
    EXPECT_GT(bound, 0) << solver;
    EXPECT_LE(bound, 1e-8) << solver;
    EXPECT_GT(figure(result, "condition_estimate"), 1) << solver;
    EXPECT_GT(figure(result, "contraction"), 0.5) << solver;
    EXPECT_LT(figure(result, "contraction"), 1) << solver;
    // The history: entries for each channel, ending at the tolerance.
    const SolveHistory& history = result.attributes.history;
    ASSERT_GT(history.size(), 3u) << solver;
    for (int c = 0; c < 3; ++c) {
      double last = -1, seconds = -1;
      for (size_t k = 0; k < history.size(); ++k) {
        if (history.channel[k] != c) continue;
        EXPECT_GE(history.seconds[k], seconds) << solver;
        last = history.residual[k];
        seconds = history.seconds[k];
      }
      EXPECT_GE(last, 0) << solver << ": no history for channel " << c;
      // (cg and gauss-seidel record the residual of their row-scaled system)
      if (solver != "cg" && solver != "gauss-seidel") {
        EXPECT_LE(last, 1e-10) << solver;
      }
    }
  }
}

// Block Gauss-Seidel sweeps each rank's rows, southwell gathers shooters across ranks and cg
// runs on the repaired F: none of that may change the answer with the rank count.
TEST_F(EndToEnd, EverySolverGivesTheSameAnswerOnOneTwoAndThreeRanks) {
  const std::string options = " --max-area 8000 --rays 64 -q --rtol 1e-10 ";
  for (const char* solver : {"gauss-seidel", "southwell", "cg", "chebyshev"}) {
    std::vector<Result> results;
    for (int ranks : {1, 2, 3}) {
      const std::string out = path(std::string(solver) + std::to_string(ranks) + ".h5");
      ProgramRun run =
          radiosity(ranks, "solve builtin:cornell" + options + "--solver " + solver + " -o " + out);
      ASSERT_EQ(run.exitCode, 0) << run.output;
      results.push_back(readResult(out));
    }
    double largest = 0;
    for (const Rgb& b : results[0].radiosity) largest = std::max({largest, b[0], b[1], b[2]});
    for (const Result& result : results) {
      EXPECT_EQ(result.mesh.triangles, results[0].mesh.triangles);
      double gap = 0;
      for (size_t i = 0; i < result.radiosity.size(); ++i)
        for (int c = 0; c < 3; ++c)
          gap = std::max(gap, std::abs(result.radiosity[i][c] - results[0].radiosity[i][c]));
      EXPECT_LE(gap / largest, 1e-8) << solver << " on " << result.attributes.ranks << " ranks";
    }
  }
}

// With no --solver the program picks one and says which and why.
TEST_F(EndToEnd, WithoutASolverTheProgramPicksOneAndSaysWhich) {
  const std::string options = " --max-area 8000 --rays 16 ";
  ProgramRun plain = radiosity(2, "solve builtin:cornell" + options + "-o " + path("a.h5"));
  ASSERT_EQ(plain.exitCode, 0) << plain.output;
  EXPECT_NE(plain.output.find("no --solver given: gmres"), std::string::npos) << plain.output;
  Result a = readResult(path("a.h5"));
  EXPECT_EQ(a.attributes.solver, "gmres");
  EXPECT_NE(a.attributes.solverChoice.find("not reciprocal"), std::string::npos);
  ProgramRun reciprocal =
      radiosity(2, "solve builtin:cornell" + options + "--reciprocity -o " + path("b.h5"));
  ASSERT_EQ(reciprocal.exitCode, 0) << reciprocal.output;
  EXPECT_EQ(readResult(path("b.h5")).attributes.solver, "cg");
}

TEST_F(EndToEnd, CornellBoxIsTheSameOnOneTwoAndThreeRanks) {
  std::string options = " --max-area 2000 --rays 128 -q ";
  ProgramRun one = radiosity(1, "solve builtin:cornell" + options + "-o " + path("one.h5"));
  ProgramRun two = radiosity(2, "solve builtin:cornell" + options + "-o " + path("two.h5"));
  ASSERT_EQ(one.exitCode, 0) << one.output;
  ASSERT_EQ(two.exitCode, 0) << two.output;
  Result a = readResult(path("one.h5")), b = readResult(path("two.h5"));
  ASSERT_EQ(a.mesh.triangles, b.mesh.triangles);
  ASSERT_EQ(a.mesh.vertices, b.mesh.vertices);
  ASSERT_EQ(a.radiosity.size(), b.radiosity.size());
  double worst = 0;
  for (size_t i = 0; i < a.radiosity.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      double scale = std::max(std::abs(a.radiosity[i][c]), 1e-300);
      worst = std::max(worst, std::abs(a.radiosity[i][c] - b.radiosity[i][c]) / scale);
    }
  }
  EXPECT_LT(worst, 1e-9);
  // Both ranks owned patches in the two-rank run.
  EXPECT_NE(std::find(b.rank.begin(), b.rank.end(), 1), b.rank.end());
  // The error figures too, on 1, 2 and 3 ranks: the calibration gathers the same patches with
  // the same random numbers and fits them in the same order; the discretisation estimate keys
  // its rays by patch. Only the products with F round differently.
  ProgramRun three = radiosity(3, "solve builtin:cornell" + options + "-o " + path("three.h5"));
  ASSERT_EQ(three.exitCode, 0) << three.output;
  const Result c = readResult(path("three.h5"));
  for (const Result* other : {static_cast<const Result*>(&b), &c}) {
    for (const char* figure : {"error_estimate", "sampling_error", "discretisation_error",
                               "error_scale_indirect_red", "error_scale_direct_blue"}) {
      const double x = a.attributes.solveFigures.at(figure),
                   y = other->attributes.solveFigures.at(figure);
      EXPECT_NEAR(y, x, 1e-6 * std::abs(x)) << figure << " on " << other->attributes.ranks;
    }
    ASSERT_EQ(other->radiosityStderr.size(), a.radiosityStderr.size());
    ASSERT_EQ(other->radiosityDiscretisation.size(), a.radiosityDiscretisation.size());
    for (size_t i = 0; i < a.radiosity.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const double scale = std::max(std::abs(a.radiosity[i][k]), 1e-300);
        EXPECT_NEAR(other->radiosityStderr[i][k], a.radiosityStderr[i][k], 1e-6 * scale);
        EXPECT_NEAR(other->radiosityDiscretisation[i][k], a.radiosityDiscretisation[i][k],
                    1e-6 * scale);
      }
    }
  }
}

}  // namespace
}  // namespace radiosity
