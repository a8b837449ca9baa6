// View3D's users' workflow end to end: a .vs3 file solved and its view factors exported in
// View3D's own output layout and as CSV, against closed forms; the estimated errors of group
// view factors against their measured errors; a thermal run on a .vs3 with its groups' table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analytic_view_factors.h"
#include "end_to_end_fixture.h"
#include "io/store/result.h"
#include "thermal_scenes.h"
#include "view3d_files.h"

namespace radiosity {
namespace {

using testing::EndToEnd;
using testing::ProgramRun;

// The largest error of a 6 × 6 table of cube face factors (rows and columns in the .vs3's face
// order: z=0, x=0, y=0, z=1, x=1, y=1: face k's opposite is k ± 3).
double largestCubeError(const std::vector<double>& f) {
  double worst = 0;
  for (size_t a = 0; a < 6; ++a)
    for (size_t b = 0; b < 6; ++b) {
      const double exact = a == b             ? 0
                           : (a + 3) % 6 == b ? testing::kCubeOpposite
                                              : testing::kCubeAdjacent;
      worst = std::max(worst, std::abs(f[a * 6 + b] - exact));
    }
  return worst;
}

// View3D's manual example read as it is published, solved on 1, 2 and 3 ranks, exported in
// View3D's layout: the exact face factors, as accurately as from an OBJ of the same cube, and
// the same table on every rank count.
TEST_F(EndToEnd, Vs3UnitCubeGivesTheExactFaceFactorsAsAnObjOfTheSameCube) {
  std::ofstream(path("cube.vs3")) << testing::kView3dCube;
  std::ofstream(path("cube.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                     "g zeq0\nf 1 2 3 4\ng xeq0\nf 1 4 8 5\ng yeq0\nf 1 5 6 2\n"
                                     "g zeq1\nf 7 6 5 8\ng xeq1\nf 7 3 2 6\ng yeq1\nf 7 8 4 3\n";
  std::vector<testing::View3dOutput> tables;
  for (int ranks : {1, 2, 3}) {
    const std::string out = path("vs3-" + std::to_string(ranks) + ".h5");
    ProgramRun run = radiosity(ranks, "solve " + path("cube.vs3") + " -q -o " + out);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const std::string text = path("vs3-" + std::to_string(ranks) + ".txt");
    run = radiosity(ranks, "export " + out + " --view-factors " + text);
    ASSERT_EQ(run.exitCode, 0) << run.output;
    tables.push_back(testing::readView3dOutput(text));
  }
  const testing::View3dOutput& table = tables[1];
  ASSERT_EQ(table.header.size(), 6u);
  EXPECT_EQ(table.header[0], "radiosity");
  EXPECT_EQ(table.header[2], "0");  // text
  EXPECT_EQ(table.header[3], "1");  // an enclosure: every row sums to 1
  EXPECT_EQ(table.header[4], "0");  // black-surface factors
  ASSERT_EQ(table.n, 6u);
  ASSERT_EQ(table.factors.size(), 36u);
  // (summed in the scene's coordinates: the unit faces' areas to an ulp, not the 6e-15 of the
  // tracing frame's round-off)
  for (double a : table.area) EXPECT_NEAR(a, 1, 4e-16);
  ASSERT_EQ(table.emissivity.size(), 6u);
  for (double e : table.emissivity) EXPECT_EQ(e, 0.5);
  for (const auto& other : tables)
    for (size_t k = 0; k < 36; ++k) EXPECT_NEAR(other.factors[k], table.factors[k], 1e-12);

  ProgramRun run = radiosity(2, "solve " + path("cube.obj") + " -q -o " + path("obj.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result obj = readResult(path("obj.h5"));
  ASSERT_EQ(obj.groups.names.size(), 6u);
  const double objError = largestCubeError(obj.groups.factors);
  const double vs3Error = largestCubeError(table.factors);
  EXPECT_LT(vs3Error, 1e-6);
  EXPECT_LE(vs3Error, std::max(2 * objError, 1e-9)) << "OBJ's: " << objError;
}

// View3D's cube with a window (a subsurface) in the middle of its z = 0 face: the window is cut
// out of the face, and the window's and the rest of the face's factors to the opposite face
// are the parallel rectangles' closed forms, within the run's stated error; every row sums to 1.
TEST_F(EndToEnd, Vs3SubsurfaceIsCutOutOfItsBaseWithExactFactors) {
  std::string cube = testing::kView3dCube;
  cube.replace(cube.find("End of data"), std::string::npos,
               "V  9  .25 .25 0.\nV 10  .75 .25 0.\nV 11  .75 .75 0.\nV 12  .25 .75 0.\n"
               "S  7    9  10  11  12   1   0   0.90  window\nEnd of data\n");
  std::ofstream(path("window.vs3")) << cube;
  const ProgramRun run =
      radiosity(2, "solve " + path("window.vs3") + " -q -o " + path("window.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result r = readResult(path("window.h5"));
  const size_t g = 7;
  ASSERT_EQ(r.groups.names.size(), g);
  EXPECT_EQ(r.groups.names[0], "zeq0");
  EXPECT_EQ(r.groups.names[6], "window");
  ASSERT_EQ(r.groups.factorError.size(), g * g);
  EXPECT_NEAR(r.groups.area[0], 0.75, 1e-12);  // the face less its window
  EXPECT_NEAR(r.groups.area[6], 0.25, 1e-12);
  const double window = testing::parallelRectangles({.25, .75, .25, .75}, {0, 1, 0, 1}, 1);
  const double wall = (testing::kCubeOpposite - 0.25 * window) / 0.75;
  for (const auto& [from, exact] : {std::pair{size_t{6}, window}, std::pair{size_t{0}, wall}}) {
    const double f = r.groups.factors[from * g + 3], error = r.groups.factorError[from * g + 3];
    std::printf("F(%s -> zeq1) = %.12f, exact %.12f, error %.2e, stated %.2e\n",
                r.groups.names[from].c_str(), f, exact, f - exact, error);
    EXPECT_LT(error, 1e-5);
    EXPECT_LE(std::abs(f - exact), 3 * error);
  }
  EXPECT_NEAR(r.groups.factors[6 * g + 0], 0, 1e-12);  // coplanar: they do not see each other
  for (size_t a = 0; a < g; ++a) {
    double sum = 0, error = 0;
    for (size_t b = 0; b < g; ++b) {
      sum += r.groups.factors[a * g + b];
      error += r.groups.factorError[a * g + b];
    }
    EXPECT_NEAR(sum, 1, std::max(3 * error, 1e-9)) << r.groups.names[a];
  }
}

// The group view factors' estimated errors against their measured errors: the unit cube cut
// into 2 × 2 squares a face, each a surface of a .vs3 (24 groups, 552 factors to other
// squares), rows sampled (not by closed forms), against the exact rectangle factors.
TEST_F(EndToEnd, GroupViewFactorErrorsMatchTheirMeasuredErrors) {
  std::ofstream(path("squares.vs3")) << testing::view3dSquares(2, 0.9);
  ProgramRun run = radiosity(2, "solve " + path("squares.vs3") +
                                    " --exact-rows off --rays 256 -q -o " + path("squares.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  run = radiosity(1, "export " + path("squares.h5") + " --view-factors " + path("f.csv"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result r = readResult(path("squares.h5"));
  const std::vector<testing::CubeSquare> squares = testing::cubeSquares(2);
  const size_t g = squares.size();
  ASSERT_EQ(r.groups.names.size(), g);
  ASSERT_EQ(r.groups.factorError.size(), g * g);
  double squaredErrors = 0, squaredEstimates = 0;
  int beyond = 0, pairs = 0;
  for (size_t a = 0; a < g; ++a)
    for (size_t b = 0; b < g; ++b) {
      if (squares[a].face == squares[b].face) continue;
      const double error =
          r.groups.factors[a * g + b] - testing::squareFactor(squares[a], squares[b]);
      const double estimate = r.groups.factorError[a * g + b];
      EXPECT_GT(estimate, 0);
      squaredErrors += error * error;
      squaredEstimates += estimate * estimate;
      beyond += std::abs(error) > 3 * estimate;
      ++pairs;
    }
  const double ratio = std::sqrt(squaredErrors / squaredEstimates);
  EXPECT_GT(ratio, 0.4) << "the estimates are too large";
  EXPECT_LT(ratio, 2.5) << "the estimates are too small";
  EXPECT_LE(beyond, pairs / 20) << "of " << pairs;
  // The CSV holds the same numbers, a row per pair.
  std::ifstream csv(path("f.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "from,to,from_name,to_name,view_factor,view_factor_error");
  size_t rows = 0;
  while (std::getline(csv, line)) {
    std::istringstream fields(line);
    std::string from, to, fromName, toName, factor, error;
    std::getline(fields, from, ',');
    std::getline(fields, to, ',');
    std::getline(fields, fromName, ',');
    std::getline(fields, toName, ',');
    std::getline(fields, factor, ',');
    std::getline(fields, error, ',');
    const size_t a = std::stoul(from), b = std::stoul(to);
    EXPECT_EQ(fromName, "s" + std::to_string(a));
    EXPECT_EQ(std::stod(factor), r.groups.factors[a * g + b]);
    EXPECT_EQ(std::stod(error), r.groups.factorError[a * g + b]);
    ++rows;
  }
  EXPECT_EQ(rows, g * g);
}

// A thermal run on the .vs3 cube (its surfaces named in the boundary conditions), the groups'
// table: the hot floor's heat rate as the result has it, and the faces' temperatures.
TEST_F(EndToEnd, ThermalVs3GivesItsGroupsTable) {
  std::ofstream(path("cube.vs3")) << testing::kView3dCube;
  // zeq0 takes the file's emissivity (0.5), the rest the boundary conditions'.
  std::ofstream(path("bc.toml")) << "[surface.\"zeq0\"]\ntemperature = 1000\n"
                                    "[surface.\"zeq1\"]\nemissivity = 0.5\ntemperature = 300\n"
                                    "[default]\nemissivity = 0.3\nheat_flux = 0\n";
  ProgramRun run = radiosity(
      2, "solve " + path("cube.vs3") + " --thermal " + path("bc.toml") + " -q -o " + path("t.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  run = radiosity(2, "export " + path("t.h5") + " --groups-csv " + path("g.csv"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result r = readResult(path("t.h5"));
  // Known temperatures reflect 1 − ε (zeq0 the file's 0.5, zeq1 the conditions' 0.5), known
  // fluxes are rows of ρ = 1.
  for (int64_t t = 0; t < r.mesh.triangleCount(); ++t)
    EXPECT_EQ(r.mesh.reflectance[t][0], r.mesh.label[t] % 3 == 0 ? 0.5 : 1.0) << t;
  std::ifstream csv(path("g.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "group,name,area,patches,radiosity,heat_rate,heat_rate_error,temperature");
  std::getline(csv, line);  // zeq0
  std::istringstream fields(line);
  std::vector<std::string> f;
  for (std::string field; std::getline(fields, field, ',');) f.push_back(field);
  ASSERT_EQ(f.size(), 8u) << line;
  EXPECT_EQ(f[1], "zeq0");
  EXPECT_EQ(std::stod(f[5]), r.groups.heatRate.at(0));
  EXPECT_GT(std::stod(f[5]), 0);  // the hot floor loses heat
  EXPECT_DOUBLE_EQ(std::stod(f[7]), 1000);
}

// What export refuses: a result without groups (exit 3, the file named: here of more labels
// than are tabled), an output that is its input (exit 2), nothing to write (exit 2); nothing is
// left behind.
TEST_F(EndToEnd, ExportRefusesWhatItCannotWrite) {
  std::ofstream obj(path("many.obj"));
  for (int k = 0; k < 1025; ++k)  // a row of triangles, each a group of its own
    obj << "v " << 2 * k << " 0 0\nv " << 2 * k + 1 << " 0 0\nv " << 2 * k << " 1 0\ng t" << k
        << "\nf " << 3 * k + 1 << " " << 3 * k + 2 << " " << 3 * k + 3 << "\n";
  obj.close();
  ProgramRun run = radiosity(1, "solve " + path("many.obj") + " -q --rays 16 -o " + path("s.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  run = radiosity(1, "export " + path("s.h5") + " --view-factors " + path("f.txt"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("s.h5"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("no group view factors"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(path("f.txt")));
  run = radiosity(1, "export " + path("s.h5") + " --groups-csv " + path("s.h5"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  run = radiosity(1, "export " + path("s.h5"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("nothing to write"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace radiosity
