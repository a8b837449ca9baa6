// Thermal runs with surroundings ([surroundings] temperature in the boundary-condition file):
// what leaves an open scene goes to black surroundings at that temperature, which send
// (1 − Σ_j F_ij) σT⁴ back into every patch. Plates that see nothing but the surroundings have
// exact answers: a plate of given temperature loses εσ(T⁴ − T_amb⁴), an adiabatic one comes to
// T_amb, one that loses q comes to (T_amb⁴ + q/(εσ))^¼; without the key, surroundings at 0 K.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "end_to_end_fixture.h"
#include "io/store/result.h"
#include "thermal_scenes.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::ProgramRun;

using testing::kSigma;
using testing::writeMaterials;

// Three unit squares in the plane z = 0, a metre apart, all facing +z: none sees another, so
// each row of F is empty and every patch sees only the surroundings.
void writePlates(const std::string& obj) {
  writeMaterials(fs::path(obj).replace_extension(".mtl").string(), {"hot", "still", "heater"});
  std::ofstream out(obj);
  out << "mtllib " << fs::path(obj).replace_extension(".mtl").filename().string() << "\n";
  const char* names[] = {"hot", "still", "heater"};
  for (int p = 0; p < 3; ++p) {
    const double x = 2.0 * p;
    out << "v " << x << " 0 0\nv " << x + 1 << " 0 0\nv " << x + 1 << " 1 0\nv " << x << " 1 0\n";
  }
  for (int p = 0; p < 3; ++p) {
    const int v = 4 * p + 1;
    out << "usemtl " << names[p] << "\nf " << v << " " << v + 1 << " " << v + 2 << " " << v + 3
        << "\n";
  }
}

const char* const kPlateConditions =
    "[surface.\"hot\"]\nemissivity = 0.7\ntemperature = 500\n"
    "[surface.\"still\"]\nemissivity = 0.6\nheat_flux = 0\n"
    "[surface.\"heater\"]\nemissivity = 0.5\nheat_flux = 1000\n";

double groupRate(const Result& r, const std::string& name) {
  for (size_t g = 0; g < r.groups.names.size(); ++g)
    if (r.groups.names[g] == name) return r.groups.heatRate.at(g);
  ADD_FAILURE() << "no group " << name;
  return 0;
}

// Per patch of the group `name`, its temperature (K) and net flux (W/m^2) are `t` and `q`.
void expectPatches(const Result& r, const std::string& name, double t, double q) {
  int32_t label = -1;
  for (size_t g = 0; g < r.groups.names.size(); ++g)
    if (r.groups.names[g] == name) label = static_cast<int32_t>(g);
  ASSERT_GE(label, 0) << name;
  int seen = 0;
  for (size_t i = 0; i < r.temperature.size(); ++i) {
    if (r.mesh.label[i] != label) continue;
    ++seen;
    ASSERT_NEAR(r.temperature[i], t, 1e-9 * t + 1e-9) << name << " patch " << i;
    ASSERT_NEAR(r.netHeatFlux[i], q, 1e-9 * std::abs(q) + 1e-9) << name << " patch " << i;
  }
  EXPECT_GT(seen, 0) << name;
}

// Surroundings at 293 K: the exact fluxes and temperatures on every patch, on 1 and 2 ranks, and
// the balance is the net flow to the surroundings, so named in the log.
TEST_F(EndToEnd, PlatesFacingSurroundingsAtAnAmbientTemperatureMeetTheirExactAnswers) {
  writePlates(path("plates.obj"));
  std::ofstream(path("bc.toml")) << kPlateConditions << "[surroundings]\ntemperature = 293.0\n";
  const double ambient = 293, hot = 0.7 * kSigma * (std::pow(500.0, 4) - std::pow(ambient, 4));
  const double heater = std::pow(std::pow(ambient, 4) + 1000 / (0.5 * kSigma), 0.25);
  for (int ranks : {1, 2}) {
    const std::string out = path("plates" + std::to_string(ranks) + ".h5");
    ProgramRun run = radiosity(
        ranks, "solve " + path("plates.obj") + " --thermal " + path("bc.toml") + " -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const Result r = readResult(out);
    RecordProperty("hot_exact_w", std::to_string(hot));
    RecordProperty("hot_computed_w", std::to_string(groupRate(r, "hot")));
    RecordProperty("heater_exact_k", std::to_string(heater));
    EXPECT_NEAR(groupRate(r, "hot"), hot, 1e-9 * hot);
    EXPECT_NEAR(groupRate(r, "still"), 0.0, 1e-9 * hot);
    EXPECT_NEAR(groupRate(r, "heater"), 1000.0, 1e-9 * 1000);
    ASSERT_NO_FATAL_FAILURE(expectPatches(r, "hot", 500, hot));
    ASSERT_NO_FATAL_FAILURE(expectPatches(r, "still", ambient, 0));
    ASSERT_NO_FATAL_FAILURE(expectPatches(r, "heater", heater, 1000));
    // Σ q A: what the plates send to the surroundings net of what comes back.
    EXPECT_NEAR(r.attributes.solveFigures.at("thermal_balance_watts"), hot + 1000,
                1e-9 * (hot + 1000));
    EXPECT_EQ(r.attributes.solveFigures.at("thermal_surroundings_kelvin"), ambient);
    EXPECT_NE(run.output.find("net flow to the surroundings at 293 K"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("mean temperature 293 K"), std::string::npos) << run.output;
  }
}

// Without [surroundings], the surroundings are at 0 K, as before the key: the hot plate loses
// εσT⁴, the adiabatic one has nothing to come to (0 K), the heater comes to (q/(εσ))^¼.
TEST_F(EndToEnd, PlatesWithoutSurroundingsRadiateToZeroKelvinAsBefore) {
  writePlates(path("plates.obj"));
  std::ofstream(path("bc.toml")) << kPlateConditions;
  ProgramRun run = radiosity(2, "solve " + path("plates.obj") + " --thermal " + path("bc.toml") +
                                    " -o " + path("plates.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result r = readResult(path("plates.h5"));
  const double hot = 0.7 * kSigma * std::pow(500.0, 4);
  EXPECT_NEAR(groupRate(r, "hot"), hot, 1e-9 * hot);
  ASSERT_NO_FATAL_FAILURE(expectPatches(r, "hot", 500, hot));
  ASSERT_NO_FATAL_FAILURE(expectPatches(r, "still", 0, 0));
  ASSERT_NO_FATAL_FAILURE(expectPatches(r, "heater", std::pow(1000 / (0.5 * kSigma), 0.25), 1000));
  EXPECT_NEAR(r.attributes.solveFigures.at("thermal_balance_watts"), hot + 1000,
              1e-9 * (hot + 1000));
  EXPECT_EQ(r.attributes.solveFigures.count("thermal_surroundings_kelvin"), 0u);
  EXPECT_NE(run.output.find("surroundings at 0 K"), std::string::npos) << run.output;
}

// A closed box has no view left for the surroundings: its rates are those without them.
TEST_F(EndToEnd, ClosedBoxIsNotReachedByItsSurroundings) {
  testing::writeCube(path("box.obj"));
  const std::string conditions =
      "[surface.\"hot\"]\nemissivity = 0.8\ntemperature = 1000.0\n"
      "[surface.\"cold\"]\nemissivity = 0.5\ntemperature = 300\n"
      "[surface.\"sides\"]\nemissivity = 0.3\nheat_flux = 0.0\n";
  std::ofstream(path("none.toml")) << conditions;
  std::ofstream(path("warm.toml")) << conditions << "[surroundings]\ntemperature = 2000\n";
  for (const char* name : {"none", "warm"}) {
    ProgramRun run = radiosity(
        2, "solve " + path("box.obj") + " --thermal " + path(std::string(name) + ".toml") +
               " --exact-rows off --patches 600 -q -o " + path(std::string(name) + ".h5"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
  }
  const Result none = readResult(path("none.h5")), warm = readResult(path("warm.h5"));
  const double hot = groupRate(none, "hot");
  EXPECT_GT(hot, 10000);
  EXPECT_NEAR(groupRate(warm, "hot"), hot, 1e-9 * hot);
  EXPECT_NEAR(groupRate(warm, "cold"), groupRate(none, "cold"), 1e-9 * hot);
}

// A surroundings temperature below 0 K or not a number: exit 3 at its line, nothing written.
TEST_F(EndToEnd, SurroundingsBelowAbsoluteZeroAreRefusedAtTheirLine) {
  writePlates(path("plates.obj"));
  for (const char* value : {"-3.0", "nan"}) {
    std::ofstream(path("bc.toml"))
        << kPlateConditions << "[surroundings]\ntemperature = " << value << "\n";
    ProgramRun run = radiosity(2, "solve " + path("plates.obj") + " --thermal " + path("bc.toml") +
                                      " -o " + path("out.h5"));
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("bc.toml:11:"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(path("out.h5")));
  }
}

}  // namespace
}  // namespace radiosity
