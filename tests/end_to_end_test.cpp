// The program as users run it: `mpiexec -n R radiosity solve ...`, checked against exact
// answers, on 1 and 2 ranks.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/io.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;

struct ProgramRun {
  int exitCode;
  std::string output;  ///< stdout and stderr
};

class EndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("radiosity-e2e-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs the program on `ranks` ranks (through mpiexec, as root and oversubscribed if need be).
  ProgramRun radiosity(int ranks, const std::string& arguments) const {
    std::string log = path("log.txt");
    std::string command = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                          std::string(MPIEXEC) + " --oversubscribe -n " + std::to_string(ranks) +
                          " " + RADIOSITY_BINARY + " " + arguments + " > " + log + " 2>&1";
    int status = std::system(command.c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }

  fs::path dir_;
};

class ClosedBox : public EndToEnd, public ::testing::WithParamInterface<double> {};

TEST_P(ClosedBox, RadiosityIsEmissionOverOneMinusReflectance) {
  const double rho = GetParam();
  std::string out = path("box.h5");
  ProgramRun run = radiosity(2, "solve 'builtin:box?rho=" + std::to_string(rho) +
                                    "&e=1' --max-area 0.02 --rays 64 -q -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(out);
  const double exact = 1.0 / (1.0 - rho);
  ASSERT_GT(result.radiosity.size(), 300u);
  for (const Rgb& b : result.radiosity) {
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(b[c], exact, 1e-6 * exact);
  }
  EXPECT_EQ(result.attributes.ranks, 2);
  EXPECT_TRUE(result.attributes.converged);
}

INSTANTIATE_TEST_SUITE_P(Reflectances, ClosedBox, ::testing::Values(0.5, 0.9, 0.99));

TEST_F(EndToEnd, CornellBoxIsTheSameOnOneAndTwoRanks) {
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
}

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
  const std::string options = " 'builtin:rooms?patches=2000' --patches 3000 --rays 16 -q -o ";
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

// Each bad input: its exit code, a message naming the problem, and no output file.
struct BadInput {
  std::string name, arguments;
  int exitCode;
  std::string messagePart;
};

class Errors : public EndToEnd, public ::testing::WithParamInterface<BadInput> {};

TEST_P(Errors, ExitWithTheContractCodeAndLeaveNoFile) {
  const BadInput& bad = GetParam();
  std::ofstream(path("rho.obj")) << "mtllib rho.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bright\n"
                                    "f 1 2 3\n";
  std::ofstream(path("rho.mtl")) << "newmtl bright\nKd 1.5 0.5 0.5\n";
  std::ofstream(path("nan.obj")) << "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n";
  std::string arguments = bad.arguments;
  for (size_t at; (at = arguments.find("DIR/")) != std::string::npos;) {
    arguments.replace(at, 4, dir_.string() + "/");
  }
  std::string out = path("out.h5");
  ProgramRun run = radiosity(2, arguments + " -o " + out);
  EXPECT_EQ(run.exitCode, bad.exitCode) << run.output;
  EXPECT_NE(run.output.find(bad.messagePart), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find("out.h5"), std::string::npos) << entry.path();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, Errors,
    ::testing::Values(BadInput{"MissingFile", "solve DIR/missing.obj", 3, "missing.obj"},
                      BadInput{"UnknownOption", "solve builtin:box --no-such-option", 2,
                               "no-such-option"},
                      BadInput{"ReflectanceAboveOne", "solve DIR/rho.obj", 3, "rho.mtl:2"},
                      BadInput{"NonFiniteVertex", "solve DIR/nan.obj", 3, "nan.obj:3"}),
    [](const auto& info) { return info.param.name; });

TEST_F(EndToEnd, FailedRunLeavesAnExistingOutputUntouched) {
  std::string out = path("keep.h5");
  std::ofstream(out) << "previous result";
  ProgramRun run = radiosity(2, "solve " + path("missing.obj") + " -o " + out);
  EXPECT_EQ(run.exitCode, 3);
  std::ifstream in(out);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "previous result");
}

TEST_F(EndToEnd, WrongWindingIsWarnedAboutNamingTheCulprits) {
  // A room whose walls are wound outward (wrong when seen from inside) around a lamp cube wound
  // outward (right for a block): the lamp's rays hit the backs of the walls.
  std::ofstream(path("room.mtl")) << "newmtl white\nKd 0.8 0.8 0.8\n"
                                     "newmtl light\nKd 0.5 0.5 0.5\nKe 1 1 1\n";
  std::ofstream obj(path("room.obj"));
  obj << "mtllib room.mtl\n";
  for (double size : {1.0, 0.5}) {  // corner i at (x, y, z) = bits of i, scaled, centred
    for (int i = 0; i < 8; ++i) {
      obj << "v " << 0.5 + size * ((i & 1) - 0.5) << " " << 0.5 + size * ((i >> 1 & 1) - 0.5) << " "
          << 0.5 + size * ((i >> 2 & 1) - 0.5) << "\n";
    }
  }
  const int outward[6][4] = {{3, 4, 2, 1}, {6, 8, 7, 5}, {2, 6, 5, 1},
                             {7, 8, 4, 3}, {5, 7, 3, 1}, {4, 8, 6, 2}};
  obj << "g walls\nusemtl white\n";
  for (const auto& f : outward)
    obj << "f " << f[0] << " " << f[1] << " " << f[2] << " " << f[3] << "\n";
  obj << "g lamp\nusemtl light\n";
  for (const auto& f : outward) {
    obj << "f " << f[0] + 8 << " " << f[1] + 8 << " " << f[2] + 8 << " " << f[3] + 8 << "\n";
  }
  obj.close();
  ProgramRun run = radiosity(
      2, "solve " + path("room.obj") + " --max-area 0.02 --rays 16 -q -o " + path("room.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("of the rays hit the back of a face"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("most hit: 'white (group walls)' 100%"), std::string::npos)
      << run.output;
}

TEST_F(EndToEnd, JobFileSetsOptionsAndTheCommandLineWins) {
  std::ofstream(path("job.toml")) << "# a job\n[solve]\nrays = 16\nsolver = \"jacobi\"\n"
                                     "max-area = 0.05  # coarse\nquiet = true\n";
  std::string out = path("job.h5");
  ProgramRun run =
      radiosity(2, "solve builtin:box --config " + path("job.toml") + " --rays 8 -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  Result result = readResult(out);
  EXPECT_EQ(result.attributes.solver, "jacobi");
  EXPECT_EQ(result.attributes.raysPerPatch, 8);
}

TEST_F(EndToEnd, JobFileWithAnUnknownKeyIsRefused) {
  std::ofstream(path("job.toml")) << "rays = 16\nrayz = 32\n";
  std::string out = path("job.h5");
  ProgramRun run = radiosity(2, "solve builtin:box --config " + path("job.toml") + " -o " + out);
  EXPECT_EQ(run.exitCode, 3);
  EXPECT_NE(run.output.find("job.toml:2: unknown key 'rayz'"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(EndToEnd, RenderWritesAPictureAndInfoDescribesTheResult) {
  std::string out = path("c.h5"), png = path("c.png");
  ASSERT_EQ(radiosity(2, "solve builtin:cornell --max-area 4000 --rays 64 -q -o " + out).exitCode,
            0);
  ProgramRun render = radiosity(2, "render " + out + " -o " + png + " --width 64 --height 48");
  ASSERT_EQ(render.exitCode, 0) << render.output;
  std::ifstream in(png, std::ios::binary);
  char signature[8] = {};
  in.read(signature, 8);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  ProgramRun info = radiosity(1, "info " + out);
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("/patches/radiosity"), std::string::npos) << info.output;
}

}  // namespace
}  // namespace radiosity
