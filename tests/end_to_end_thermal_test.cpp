// Thermal radiation exchange as users get it from `radiosity solve --thermal`: concentric
// spheres against their closed form on 1, 2 and 3 ranks, a closed box with a hot floor, a cold
// ceiling and adiabatic sides against a dense solve with exact rectangle view factors, and bad
// boundary-condition files refused before anything is written.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "analytic_view_factors.h"
#include "end_to_end_fixture.h"
#include "io/store/result.h"
#include "thermal_scenes.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::ProgramRun;
using testing::Rectangle;

using testing::cubeHeatRate;
using testing::kSigma;
using testing::writeCube;
using testing::writeSpheres;
using testing::writeZonedSphere;

// A group's heat rate and its estimated error in a result.
struct Rate {
  double watts, error;
};
Rate groupRate(const Result& r, const std::string& name) {
  for (size_t g = 0; g < r.groups.names.size(); ++g)
    if (r.groups.names[g] == name) return {r.groups.heatRate.at(g), r.groups.heatRateError.at(g)};
  ADD_FAILURE() << "no group " << name;
  return {0, 0};
}

TEST(AnalyticViewFactors, PerpendicularRectanglesAnywhereMeetTheSharedEdgeFormula) {
  // Sharing a whole edge: Howell's C-14.
  EXPECT_NEAR(testing::perpendicularRectangles({0, 2, 0, 0.5}, {0, 2, 0, 3}),
              testing::perpendicularRectangles(2, 0.5, 3), 1e-12);
  // Apart: by additivity, what the whole shared-edge rectangle sees of [0,2]×[0,3] is the sum
  // over its two halves, each weighted by its area.
  const double whole = testing::perpendicularRectangles({0, 2, 0, 1}, {0, 2, 0, 3});
  const double near = testing::perpendicularRectangles({0, 2, 0, 0.5}, {0, 2, 0, 3});
  const double far = testing::perpendicularRectangles({0, 2, 0.5, 1}, {0, 2, 0, 3});
  EXPECT_NEAR(whole, 0.5 * near + 0.5 * far, 1e-12);
  // And split along the common line: [0,2] = [0,0.7] ∪ [0.7,2] on the far side.
  const double left = testing::perpendicularRectangles({0, 2, 0.5, 1}, {0, 0.7, 0, 3});
  const double right = testing::perpendicularRectangles({0, 2, 0.5, 1}, {0.7, 2, 0, 3});
  EXPECT_NEAR(far, left + right, 1e-12);
}

// Two concentric grey spheres: every ray of the inner one reaches the outer one, so
// q1 A1 = σ(T1⁴ − T2⁴) A1 / (1/ε1 + (A1/A2)(1/ε2 − 1)) (the facets' areas), the same on 1, 2
// and 3 ranks, the balance closed to round-off, within 0.5 % and within the reported error.
TEST_F(EndToEnd, ConcentricSpheresExchangeTheExactHeatRateOnOneTwoAndThreeRanks) {
  const auto [a1, a2] = writeSpheres(path("spheres.obj"), 2);
  std::ofstream(path("bc.toml")) << "[surface.\"inner\"]\nemissivity = 0.6\ntemperature = 800\n"
                                    "[surface.\"outer\"]\nemissivity = 0.4\ntemperature = 300\n";
  const double exact =
      kSigma * (std::pow(800.0, 4) - std::pow(300.0, 4)) * a1 / (1 / 0.6 + a1 / a2 * (1 / 0.4 - 1));
  std::vector<Result> results;
  const std::string options = std::string(" ")
                                  .append(path("spheres.obj"))
                                  .append(" --thermal ")
                                  .append(path("bc.toml"))
                                  .append(" -q -o ");
  ASSERT_NO_FATAL_FAILURE(solveOnEach({{1, 1}, {2, 1}, {3, 1}}, options, results));
  for (const Result& r : results) {
    EXPECT_EQ(r.attributes.channels, 1);
    EXPECT_FALSE(r.attributes.thermal.empty());
    ASSERT_EQ(r.temperature.size(), r.radiosity.size());
    const Rate inner = groupRate(r, "inner"), outer = groupRate(r, "outer");
    // (the figures docs/thermal.md quotes: --gtest_output=xml:FILE records them)
    RecordProperty("inner_watts_minus_exact", std::to_string(inner.watts - exact));
    RecordProperty("inner_error", std::to_string(inner.error));
    RecordProperty("outer_error", std::to_string(outer.error));
    std::ostringstream balance;
    balance << (inner.watts + outer.watts) / exact;
    RecordProperty("balance_share", balance.str());
    EXPECT_NEAR(inner.watts, exact, 0.005 * exact);
    EXPECT_LE(std::abs(inner.watts - exact), inner.error);
    EXPECT_LE(std::abs(-outer.watts - exact), outer.error);
    EXPECT_NEAR(inner.watts + outer.watts, 0.0, 1e-9 * exact);  // reciprocity and closure
    EXPECT_NEAR(inner.watts, groupRate(results[0], "inner").watts, 1e-6 * exact);
    for (size_t i = 0; i < r.temperature.size(); ++i) {
      ASSERT_TRUE(r.temperature[i] == 800.0 || r.temperature[i] == 300.0);
      // The flux of each patch is J − H (W/m^2), positive on the hot sphere.
      ASSERT_DOUBLE_EQ(r.netHeatFlux[i], r.radiosity[i][0] - r.irradiance[i][0]);
      ASSERT_EQ(r.netHeatFlux[i] > 0, r.temperature[i] == 800.0);
    }
  }
}

// A black inner sphere (ε = 1: ρ = 0, so J carries no trace of H and its error comes from H's
// own): its rate within 0.5 % of the closed form and within its estimated error, which is there.
TEST_F(EndToEnd, BlackSurfacesHeatRateHasAnEstimatedError) {
  const auto [a1, a2] = writeSpheres(path("spheres.obj"), 2);
  std::ofstream(path("bc.toml")) << "[surface.\"inner\"]\nemissivity = 1\ntemperature = 800\n"
                                    "[surface.\"outer\"]\nemissivity = 0.5\ntemperature = 300\n";
  const double exact =
      kSigma * (std::pow(800.0, 4) - std::pow(300.0, 4)) * a1 / (1 + a1 / a2 * (1 / 0.5 - 1));
  ProgramRun run = radiosity(2, "solve " + path("spheres.obj") + " --thermal " + path("bc.toml") +
                                    " -q -o " + path("black.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(run.output.find("not estimated"), std::string::npos) << run.output;
  const Rate inner = groupRate(readResult(path("black.h5")), "inner");
  RecordProperty("exact", std::to_string(exact));
  RecordProperty("inner_watts_minus_exact", std::to_string(inner.watts - exact));
  RecordProperty("inner_error", std::to_string(inner.error));
  EXPECT_NEAR(inner.watts, exact, 0.005 * exact);
  EXPECT_GT(inner.error, 0);
  EXPECT_LE(std::abs(inner.watts - exact), inner.error) << inner.watts - exact;
  EXPECT_LT(inner.error, 0.01 * exact);
}

// A closed unit cube, the floor at 1000 K (ε 0.8), the ceiling at 300 K (ε 0.5), the sides
// adiabatic (heat_flux 0): exact rows by default, the floor's rate against a dense solve over
// squares with exact rectangle view factors (16 × 16 a face, its own discretisation error
// bounded by half its change from 8 × 8), the sides' rate 0 and their temperature between.
TEST_F(EndToEnd, ClosedBoxWithAdiabaticSidesMatchesADenseSolveWithExactRectangleFactors) {
  writeCube(path("box.obj"));
  std::ofstream(path("bc.toml")) << "[surface.\"hot\"]\nemissivity = 0.8\ntemperature = 1000.0\n"
                                    "[surface.\"cold\"]\nemissivity = 0.5\ntemperature = 300\n"
                                    "[surface.\"sides\"]\nemissivity = 0.3\nheat_flux = 0.0\n";
  ProgramRun run = radiosity(
      2, "solve " + path("box.obj") + " --thermal " + path("bc.toml") + " -o " + path("box.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("'hot': "), std::string::npos) << run.output;
  const Result r = readResult(path("box.h5"));
  const double coarse = cubeHeatRate(8, 0.8, 1000, 0.5, 300);
  const double fine = cubeHeatRate(16, 0.8, 1000, 0.5, 300);
  const Rate hot = groupRate(r, "hot"), cold = groupRate(r, "cold"), sides = groupRate(r, "sides");
  EXPECT_NEAR(hot.watts, fine, 0.005 * fine);
  EXPECT_LE(std::abs(hot.watts - fine), hot.error + 0.5 * std::abs(fine - coarse));
  EXPECT_NEAR(hot.watts + cold.watts, 0.0, 1e-8 * fine);
  EXPECT_NEAR(sides.watts, 0.0, 1e-8 * fine);
  for (size_t i = 0; i < r.temperature.size(); ++i)
    ASSERT_TRUE(r.temperature[i] >= 300 && r.temperature[i] <= 1000) << r.temperature[i];
  // The other commands take the one-channel result: a picture, a listing, a path-traced check.
  ProgramRun render = radiosity(1, "render " + path("box.h5") + " -o " + path("box.png"));
  EXPECT_EQ(render.exitCode, 0) << render.output;
  EXPECT_TRUE(fs::exists(path("box.png")));
  ProgramRun info = radiosity(1, "info " + path("box.h5"));
  EXPECT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("/patches/temperature"), std::string::npos) << info.output;
  const size_t display = info.output.find("/display/radiosity");
  ASSERT_NE(display, std::string::npos) << info.output;
  const std::string line = info.output.substr(display, info.output.find('\n', display) - display);
  EXPECT_NE(line.find(", 1]"), std::string::npos) << line;  // one channel, as /patches has
  // verify reports the one channel as one ("grey"), not as three equal colours.
  ProgramRun verify =
      radiosity(2, "verify " + path("box.h5") + " --patches 20 --paths 256 --tol 1 --csv " +
                       path("box.csv"));
  EXPECT_EQ(verify.exitCode, 0) << verify.output;
  EXPECT_NE(verify.output.find("grey"), std::string::npos) << verify.output;
  EXPECT_EQ(verify.output.find("green"), std::string::npos) << verify.output;
  std::ifstream csv(path("box.csv"));
  int rows = 0;
  for (std::string row; std::getline(csv, row);) rows += row.find(",grey,") != std::string::npos;
  EXPECT_EQ(rows, 20);
}

// Three surfaces inside a sphere, a textbook enclosure whose network solution is exact for a
// sphere: every point sees each zone with F = A_zone / A, so each zone's radiosity is uniform
// and J = E + ρ F J is three equations. A hot cap (900 K, ε 0.7), a re-radiating band (ε 0.4,
// heat_flux 0) and a cold cap (350 K, ε 0.9). The icosphere's facets see each other only nearly
// so (0.05 % in the rates at 1,280 facets): within 0.5 %, the band's temperature within 0.1 %.
TEST_F(EndToEnd, ThreeSurfaceSphericalEnclosureMeetsItsNetworkSolution) {
  const std::array<double, 3> area = writeZonedSphere(path("zones.obj"), 3);
  std::ofstream(path("bc.toml")) << "[surface.hot]\nemissivity = 0.7\ntemperature = 900\n"
                                    "[surface.band]\nemissivity = 0.4\nheat_flux = 0\n"
                                    "[surface.cold]\nemissivity = 0.9\ntemperature = 350\n";
  const double total = area[0] + area[1] + area[2];
  const std::array<double, 3> rho = {0.3, 1.0, 0.1};
  const std::array<double, 3> e = {0.7 * kSigma * std::pow(900.0, 4), 0.0,
                                   0.9 * kSigma * std::pow(350.0, 4)};
  // J_i = E_i + ρ_i H with H = Σ_j A_j J_j / A the same for every zone: H = Σ A_j E_j /
  // (A − Σ A_j ρ_j).
  double numerator = 0, denominator = total;
  for (int z = 0; z < 3; ++z) {
    numerator += area[z] * e[z];
    denominator -= area[z] * rho[z];
  }
  const double h = numerator / denominator;
  const double hotRate = (e[0] + rho[0] * h - h) * area[0];
  const double bandTemperature = std::pow(h / kSigma, 0.25);
  ProgramRun run = radiosity(2, "solve " + path("zones.obj") + " --thermal " + path("bc.toml") +
                                    " -q -o " + path("zones.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result r = readResult(path("zones.h5"));
  EXPECT_NEAR(groupRate(r, "hot").watts, hotRate, 0.005 * hotRate);
  EXPECT_NEAR(groupRate(r, "cold").watts, -hotRate, 0.005 * hotRate);
  EXPECT_NEAR(groupRate(r, "band").watts, 0.0, 1e-9 * hotRate);
  double band = 0, bandArea = 0;
  for (size_t i = 0; i < r.temperature.size(); ++i) {
    if (r.mesh.labelNames.at(r.mesh.label.at(i)) != "band") continue;
    band += r.temperature[i] * r.area[i];
    bandArea += r.area[i];
  }
  EXPECT_NEAR(band / bandArea, bandTemperature, 1e-3 * bandTemperature);
}

// The published Cornell box as users' copies have it, the floor one quad running under the
// blocks, against the hand-cut floor: a hot light (600 K), re-radiating blocks, the rest at 300 K,
// open to 0 K at the front. The heat rates and the blocks' temperatures agree within their
// estimated errors; the patches under the blocks exchange nothing; what leaves through the
// opening is the balance, positive and less than the light and walls give.
TEST_F(EndToEnd, CornellBoxOnItsUncutFloorGivesTheHandCutFloorsHeat) {
  std::ofstream(path("bc.toml")) << "[surface.light]\nemissivity = 0.9\ntemperature = 600\n"
                                    "[surface.\"short block\"]\nemissivity = 0.5\nheat_flux = 0\n"
                                    "[surface.\"tall block\"]\nemissivity = 0.5\nheat_flux = 0\n"
                                    "[default]\nemissivity = 0.9\ntemperature = 300\n";
  std::vector<Result> results;
  for (const char* floor : {"0", "1"}) {
    const std::string out = path(std::string("cut") + floor + ".h5");
    ProgramRun run = radiosity(2, std::string("solve 'builtin:cornell?cut_floor=") + floor +
                                      "' --thermal " + path("bc.toml") + " -q -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    results.push_back(readResult(out));
  }
  const Result &uncut = results[0], &cut = results[1];
  for (const std::string name : {"light", "floor", "back wall"}) {
    const Rate a = groupRate(uncut, name), b = groupRate(cut, name);
    EXPECT_NEAR(a.watts, b.watts, a.error + b.error) << name;
    EXPECT_GT(std::abs(a.watts), 0) << name;
  }
  auto meanTemperature = [](const Result& r, const std::string& name, double& area) {
    double sum = 0;
    area = 0;
    for (size_t i = 0; i < r.temperature.size(); ++i) {
      if (r.mesh.labelNames.at(r.mesh.label.at(i)) != name ||
          (!r.hidden.empty() && r.hidden[i] != 0))
        continue;
      sum += r.temperature[i] * r.area[i];
      area += r.area[i];
    }
    return sum / area;
  };
  for (const std::string name : {"short block", "tall block"}) {
    double areaUncut = 0, areaCut = 0;
    EXPECT_NEAR(meanTemperature(uncut, name, areaUncut), meanTemperature(cut, name, areaCut), 1.0)
        << name;  // estimated 0.4-0.8 K on each
  }
  ASSERT_FALSE(uncut.hidden.empty());  // the floor under the blocks, once cut along them
  double balance = 0, given = 0;
  for (size_t i = 0; i < uncut.netHeatFlux.size(); ++i) {
    if (uncut.hidden[i] != 0) {
      ASSERT_EQ(uncut.netHeatFlux[i], 0.0) << i;
    }
    balance += uncut.netHeatFlux[i] * uncut.area[i] * 1e-6;  // mm^2 -> m^2
    given += std::max(0.0, uncut.netHeatFlux[i]) * uncut.area[i] * 1e-6;
  }
  EXPECT_NEAR(balance, testing::figure(uncut, "thermal_balance_watts"), 1e-9 * given);
  EXPECT_GT(balance, 0);
  EXPECT_LT(balance, given);
}

// One F, many solves: a run's checkpoint gives its form factors to a run with other
// temperatures (--formfactors-from, on another rank count): no rays for F, and the same answer
// as a fresh run of those temperatures (the same seed: the same F), up to solver round-off.
// What it cannot serve is refused: another geometry, a result file, more rounds.
TEST_F(EndToEnd, FormFactorsFromACheckpointServeOtherTemperaturesWithoutRays) {
  writeSpheres(path("spheres.obj"), 1);
  std::ofstream(path("first.toml")) << "[surface.inner]\nemissivity = 0.6\ntemperature = 800\n"
                                       "[surface.outer]\nemissivity = 0.4\ntemperature = 300\n";
  std::ofstream(path("second.toml")) << "[surface.inner]\nemissivity = 0.3\nheat_flux = 5000\n"
                                        "[surface.outer]\nemissivity = 0.8\ntemperature = 400\n";
  const std::string options = " --rays 128 --refine-rounds 0",
                    scene = path("spheres.obj") + options;
  ProgramRun first =
      radiosity(2, "solve " + scene + " --thermal " + path("first.toml") + " --checkpoint " +
                       path("first.ckpt") + " -o " + path("first.h5"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  ProgramRun reused =
      radiosity(3, "solve " + path("spheres.obj") + options + " --thermal " + path("second.toml") +
                       " --formfactors-from " + path("first.ckpt") + " -o " + path("reused.h5"));
  ASSERT_EQ(reused.exitCode, 0) << reused.output;
  EXPECT_NE(reused.output.find("reused from"), std::string::npos) << reused.output;
  // (its patches too: no meshing, the same patches, whatever meshing would make now)
  EXPECT_NE(reused.output.find("patches taken from " + path("first.ckpt")), std::string::npos)
      << reused.output;
  ProgramRun fresh = radiosity(
      2, "solve " + scene + " --thermal " + path("second.toml") + " -o " + path("fresh.h5"));
  ASSERT_EQ(fresh.exitCode, 0) << fresh.output;
  const Result a = readResult(path("reused.h5")), b = readResult(path("fresh.h5"));
  ASSERT_EQ(a.temperature.size(), b.temperature.size());
  for (size_t i = 0; i < a.temperature.size(); ++i)
    ASSERT_NEAR(a.temperature[i], b.temperature[i], 1e-6 * b.temperature[i]) << i;
  EXPECT_NEAR(groupRate(a, "outer").watts, groupRate(b, "outer").watts,
              1e-6 * std::abs(groupRate(b, "outer").watts));
  EXPECT_NEAR(groupRate(a, "inner").watts, 5000 * a.groups.area[0], 1e-6 * 5000 * a.groups.area[0]);
  EXPECT_NE(a.attributes.options.find("formfactors-from"), std::string::npos);
  // A restart of that checkpoint with the other temperatures: the same.
  ProgramRun restarted =
      radiosity(1, "solve " + scene + " --thermal " + path("second.toml") + " --restart " +
                       path("first.ckpt") + " -o " + path("restarted.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  EXPECT_NE(restarted.output.find("for other materials than its own"), std::string::npos);
  const Result c = readResult(path("restarted.h5"));
  EXPECT_NEAR(groupRate(c, "outer").watts, groupRate(b, "outer").watts,
              1e-6 * std::abs(groupRate(b, "outer").watts));
  // Refused: another geometry, a result instead of a checkpoint, --target-error.
  writeCube(path("box.obj"));
  std::ofstream(path("box.toml")) << "[default]\nemissivity = 0.5\ntemperature = 300\n";
  ProgramRun other =
      radiosity(1, "solve " + path("box.obj") + " --thermal " + path("box.toml") +
                       " --formfactors-from " + path("first.ckpt") + " -o " + path("other.h5"));
  EXPECT_EQ(other.exitCode, 3) << other.output;
  EXPECT_NE(other.output.find("another scene"), std::string::npos) << other.output;
  ProgramRun result =
      radiosity(1, "solve " + scene + " --thermal " + path("second.toml") + " --formfactors-from " +
                       path("first.h5") + " -o " + path("other.h5"));
  EXPECT_EQ(result.exitCode, 3) << result.output;
  EXPECT_NE(result.output.find("--formfactors-from takes the checkpoint"), std::string::npos);
  ProgramRun target = radiosity(1, "solve " + scene + " --formfactors-from " + path("first.ckpt") +
                                       " --target-error 0.1 -o " + path("other.h5"));
  EXPECT_EQ(target.exitCode, 2) << target.output;
  ProgramRun rounds =
      radiosity(1, "solve " + path("spheres.obj") + " --refine-rounds 1 " + "--formfactors-from " +
                       path("first.ckpt") + " -o " + path("other.h5"));
  EXPECT_EQ(rounds.exitCode, 2) << rounds.output;
  EXPECT_NE(rounds.output.find("no --refine-rounds"), std::string::npos) << rounds.output;
  EXPECT_FALSE(fs::exists(path("other.h5")));
}

// Without --estimator, a run reusing a checkpoint's F samples as that run did: `auto` chooses by
// what emits (hemisphere where nearly all the area emits, mis where a light is a small share of
// it), and other emitters must not make a reuse refused for an estimator the user never named.
TEST_F(EndToEnd, FormFactorsFromACheckpointKeepItsEstimatorWhereNoneIsGiven) {
  writeSpheres(path("spheres.obj"), 1);
  const auto emitting = [&](bool outer) {
    std::ofstream(path("spheres.mtl")) << "newmtl inner\nKd 0.5 0.5 0.5\nKe 1 1 1\n"
                                       << "newmtl outer\nKd 0.5 0.5 0.5\n"
                                       << (outer ? "Ke 1 1 1\n" : "");
  };
  const std::string options = " --rays 64 --refine-rounds 0";
  emitting(true);  // both spheres glow: hemisphere
  ProgramRun first = radiosity(1, "solve " + path("spheres.obj") + options + " --checkpoint " +
                                      path("all.ckpt") + " -o " + path("all.h5"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  ASSERT_NE(first.output.find("no --estimator given: hemisphere"), std::string::npos)
      << first.output;
  emitting(false);  // the inner sphere alone, a fifth of the area: auto takes mis
  ProgramRun fresh =
      radiosity(1, "solve " + path("spheres.obj") + options + " -o " + path("fresh.h5"));
  ASSERT_EQ(fresh.exitCode, 0) << fresh.output;
  ASSERT_NE(fresh.output.find("no --estimator given: mis"), std::string::npos) << fresh.output;
  ProgramRun lit = radiosity(2, "solve " + path("spheres.obj") + options + " --formfactors-from " +
                                    path("all.ckpt") + " -o " + path("lit.h5"));
  ASSERT_EQ(lit.exitCode, 0) << lit.output;
  EXPECT_NE(lit.output.find("no --estimator given: hemisphere, as " + path("all.ckpt")),
            std::string::npos)
      << lit.output;
  EXPECT_NE(lit.output.find("no rays cast"), std::string::npos) << lit.output;
  EXPECT_TRUE(fs::exists(path("lit.h5")));
  // A named estimator other than the checkpoint's is the user's: refused, naming it.
  ProgramRun named =
      radiosity(1, "solve " + path("spheres.obj") + options + " --estimator mis" +
                       " --formfactors-from " + path("all.ckpt") + " -o " + path("named.h5"));
  EXPECT_EQ(named.exitCode, 3) << named.output;
  EXPECT_NE(named.output.find("estimator: hemisphere there, mis now"), std::string::npos)
      << named.output;
  EXPECT_FALSE(fs::exists(path("named.h5")));
}

// A boundary-condition file with a problem: exit 3, the file and line named, nothing written;
// an output that is the boundary-condition file itself: refused before the solve.
TEST_F(EndToEnd, ThermalFileProblemsAreRefusedBeforeAnythingIsWritten) {
  writeCube(path("box.obj"));
  std::ofstream(path("bc.toml")) << "[surface.\"hot\"]\nemissivity = 0.8\ntemperature = 1000\n"
                                    "[surface.\"cold\"]\nemissivity = 1.8\ntemperature = 300\n";
  ProgramRun run = radiosity(
      2, "solve " + path("box.obj") + " --thermal " + path("bc.toml") + " -o " + path("out.h5"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("bc.toml:5:"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  std::ofstream(path("bc.toml")) << "[surface.\"hot\"]\nemissivity = 0.8\ntemperature = 1000\n";
  run = radiosity(
      1, "solve " + path("box.obj") + " --thermal " + path("bc.toml") + " -o " + path("out.h5"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("has no condition"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  run = radiosity(
      1, "solve " + path("box.obj") + " --thermal " + path("bc.toml") + " -o " + path("bc.toml"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
}

}  // namespace
}  // namespace radiosity
