// What goes into the program and what it leaves: bad input refused with its exit code and a
// message naming the problem, outputs that would destroy something refused before any work,
// stale temporaries, job files, warnings, and the picture and description of a result.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "end_to_end_fixture.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::EndToEnd;
using testing::ProgramRun;

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
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  std::ofstream(path("nomtl.obj")) << "mtllib nowhere.mtl\n" << triangle << "f 1 2 3\n";
  std::ofstream(path("index.obj")) << triangle << "f 1 2 9\n";
  std::ofstream(path("absurd.obj")) << "v 1e31 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(path("emit.obj")) << "mtllib emit.mtl\n" << triangle << "usemtl e\nf 1 2 3\n";
  std::ofstream(path("emit.mtl")) << "newmtl e\nKe -1 0 0\n";
  std::ofstream(path("empty.obj")) << "# nothing here\n\n";
  std::ofstream(path("degenerate.obj")) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  std::ofstream(path("garbage.obj"), std::ios::binary) << std::string(
                                                              "\x7f"
                                                              "ELF\x02\x01\0\0",
                                                              8)
                                                       << "\nf 1 2 3\n";
  std::ofstream(path("twice.toml")) << "rays = 64\n# again\nrays = 128\n";
  std::ofstream(path("bow.obj")) << "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n";
  std::ofstream(path("quote.toml")) << "scene = \"builtin:box\n";
  std::ofstream(path("type.toml")) << "rays = \"abc\"\n";
  std::ofstream(path("table.toml")) << "rays = 16\n[render]\nwidth = 64\n";
  std::ofstream(path("words.h5")) << "an HDF5 scene in name only\n";
  fs::create_directory(path("folder"));
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
    ::testing::Values(
        BadInput{"MissingFile", "solve DIR/missing.obj", 3, "missing.obj"},
        BadInput{"UnknownOption", "solve builtin:box --no-such-option", 2, "no-such-option"},
        BadInput{"ReflectanceAboveOne", "solve DIR/rho.obj", 3, "rho.mtl:2"},
        BadInput{"NonFiniteVertex", "solve DIR/nan.obj", 3, "nan.obj:3"},
        BadInput{"MissingMtllib", "solve DIR/nomtl.obj", 3, "nomtl.obj:1"},
        BadInput{"IndexOutOfRange", "solve DIR/index.obj", 3, "index.obj:4"},
        BadInput{"AbsurdCoordinate", "solve DIR/absurd.obj", 3, "absurd.obj:1"},
        BadInput{"NegativeEmission", "solve DIR/emit.obj", 3, "emit.mtl:2"},
        BadInput{"EmptyScene", "solve DIR/empty.obj", 3, "no triangles"},
        BadInput{"OnlyDegenerateTriangles", "solve DIR/degenerate.obj", 3, "no triangles"},
        BadInput{"BinaryGarbage", "solve DIR/garbage.obj", 3, "garbage.obj:1"},
        BadInput{"SceneFileNotHdf5", "solve DIR/words.h5", 3, "words.h5: not an HDF5 file"},
        BadInput{"UnknownBuiltinParameter", "solve 'builtin:box?foo=1'", 3, "foo"},
        BadInput{"BadJobFileLine", "solve builtin:box --config DIR/nan.obj", 3, "nan.obj:1"},
        // Numeric options: finite and in range, or refused naming the option and the range.
        BadInput{"NanMaxArea", "solve builtin:box --max-area nan", 2, "--max-area: 'nan'"},
        BadInput{"ZeroMaxArea", "solve builtin:box --max-area 0", 2, "(0, 1e+300]"},
        BadInput{"NanRtol", "solve builtin:box --rtol nan", 2, "--rtol: 'nan'"},
        BadInput{"HugeRtol", "solve builtin:box --rtol 1e400", 2, "(0, 1]"},
        BadInput{"NanDropThreshold", "solve builtin:box --drop-threshold nan", 2,
                 "--drop-threshold: 'nan'"},
        BadInput{"NanTargetError", "solve builtin:box --target-error nan", 2,
                 "--target-error: 'nan'"},
        BadInput{"NanCheckpointEvery", "solve builtin:box --checkpoint-every nan", 2,
                 "--checkpoint-every: 'nan'"},
        BadInput{"UnknownExactRowsMode", "solve builtin:box --exact-rows on", 2,
                 "--exact-rows: on not in {auto,off}"},
        BadInput{"UnknownFormFactorPrecision", "solve builtin:box --formfactor-precision half", 2,
                 "--formfactor-precision: half not in {auto,single,double}"},
        BadInput{"NegativeSeed", "solve builtin:box --seed -1", 2, "--seed: '-1'"},
        BadInput{"SeedAbove64Bits", "solve builtin:box --seed 99999999999999999999", 2,
                 "[0, 18446744073709551615]"},
        // Work that cannot fit is refused before it is attempted, saying how much it needs.
        BadInput{"TrillionPatches", "solve builtin:box --patches 1000000000000", 2,
                 "GB for the mesh alone"},
        BadInput{"TinyAreaBound", "solve builtin:box --max-area 1e-300", 2, "ask for fewer"},
        // ... and F is predicted after meshing, before a ray is cast.
        BadInput{"FormFactorsBeyondMemory", "solve builtin:box --patches 200000 --rays 1000000000",
                 2, "F may hold up to 4e+10 nonzeros"},
        // Job files: every error with its file and line; only small regular files are read.
        BadInput{"JobFileKeyTwice", "solve builtin:box --config DIR/twice.toml", 3,
                 "twice.toml:3: 'rays' is given twice (first on line 1)"},
        BadInput{"JobFileUnterminatedQuote", "solve --config DIR/quote.toml", 3,
                 "quote.toml:1:21: error while parsing string"},
        BadInput{"JobFileTypeError", "solve builtin:box --config DIR/type.toml", 3,
                 "type.toml:1: --rays"},
        BadInput{"JobFileOtherTable", "solve builtin:box --config DIR/table.toml", 3,
                 "table.toml:2: 'render' must be a single value, found a table"},
        BadInput{"JobFileIsADirectory", "solve builtin:box --config DIR/folder", 3,
                 "not a regular file"},
        BadInput{"JobFileIsADevice", "solve builtin:box --config /dev/zero", 3,
                 "/dev/zero: not a job file"},
        BadInput{"UnknownCommand", "foo", 2, "unknown command 'foo': the commands are solve,"},
        BadInput{"NoCommand", "-q", 2, "no command given: the commands are solve,"},
        // A bowtie has no inside: it used to become two opposite-facing triangles silently.
        BadInput{"BowtieFace", "solve DIR/bow.obj", 3, "bow.obj:5: the face's outline crosses"}),
    [](const auto& info) { return info.param.name; });

// Outputs that would destroy something, or cannot be written, are refused at once (exit 2)
// and nothing is touched: a device or pipe is not replaced by a regular file, an input is not
// overwritten, one file is not two outputs, a missing directory fails before the solve.
TEST_F(EndToEnd, OutputsThatWouldDestroySomethingAreRefusedBeforeAnyWork) {
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(path("scene.obj")) << triangle;
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0644), 0);
  fs::create_directory(path("folder"));
  struct Case {
    std::string arguments, messagePart;
  };
  const std::vector<Case> cases = {
      {"solve builtin:box --rays 16 -o " + path("pipe"), "is not a regular file"},
      {"solve builtin:box --rays 16 -o " + path("folder"), "is not a regular file"},
      {"solve " + path("scene.obj") + " --rays 16 -o " + path("scene.obj"), "is also an input"},
      {"solve " + path("scene.obj") + " --rays 16 --checkpoint " + path("scene.obj") + " -o " +
           path("x.h5"),
       "is also an input"},
      {"solve builtin:box --rays 16 --checkpoint " + path("x.h5") + " -o " + path("x.h5"),
       "is named for two outputs"},
      {"solve builtin:box --rays 16 -o " + path("nodir/x.h5"), "no directory"},
      {"study builtin:box --rays 16 -o " + path("st.csv") + " --plot " + path("st.csv"),
       "is named for two outputs"},
      {"scene cornell -o " + path("pipe"), "is not a regular file"},
      {"scene " + path("scene.obj") + " -o " + path("scene.obj"), "is also an input"},
      // (`-` is standard output to a Unix tool: not a file named `-` and `-.mtl`)
      {"scene cornell -o -", "standard output is not an output"},
      {"solve builtin:box --rays 16 -o -", "standard output is not an output"},
  };
  for (const Case& c : cases) {
    ProgramRun run = radiosity(2, c.arguments);
    EXPECT_EQ(run.exitCode, 2) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.messagePart), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("form factors:"), std::string::npos) << "work was done first";
  }
  EXPECT_TRUE(fs::is_fifo(path("pipe")));
  EXPECT_TRUE(fs::is_directory(path("folder")));
  EXPECT_TRUE(testing::readText(path("scene.obj")) == triangle) << "the input was overwritten";
  for (const char* name : {"x.h5", "st.csv", "nodir"}) EXPECT_FALSE(fs::exists(path(name))) << name;
}

// One of our options spelt with one dash would go to PETSc, which ignores it (the run would go on
// with the default 1024 rays): refused before any work with the spelling meant, exit 2; PETSc's
// own options with one dash, -help and -version included, go on to PETSc.
TEST_F(EndToEnd, OurOptionsWithOneDashAreRefusedWithTheSpellingMeant) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"solve builtin:box -rays 16 -o " + path("x.h5"), "rays"},
      {"solve builtin:box --rays 16 -o " + path("x.h5") + " -seed 3", "seed"},
      {"render " + path("x.h5") + " -output " + path("x.png"), "output"}};
  for (const auto& [arguments, name] : cases) {
    ProgramRun run = radiosity(1, arguments);
    EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find("did you mean --" + name + "?"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("form factors:"), std::string::npos) << "work was done first";
  }
  EXPECT_FALSE(fs::exists(path("x.h5")));
  ProgramRun petsc =
      radiosity(1, "solve builtin:box --rays 16 -q -o " + path("x.h5") + " -ksp_type gmres");
  EXPECT_EQ(petsc.exitCode, 0) << petsc.output;
}

// The cleanup of temporaries that killed runs left behind removes only ours (NAME.tmp.radiosity-
// [<host>-]<pid>-<hex>, a name only the program gives, of a process that is gone: 9999999 is
// beyond any pid_max), never a user's file that shares the prefix.
TEST_F(EndToEnd, StaleTemporaryCleanupRemovesOnlyOurOwn) {
  std::ofstream(path("keep.h5.tmp.notes")) << "my notes";
  std::ofstream(path("keep.h5.tmp.123.0000abcd")) << "a user's";
  ProgramRun first =
      radiosity(2, "solve builtin:box --max-area 0.05 --rays 16 -q -o " + path("stale.h5"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  fs::copy_file(path("stale.h5"),
                path("keep.h5.tmp.radiosity-9999999-0badcafe"));  // a killed run's
  ProgramRun run =
      radiosity(2, "solve builtin:box --max-area 0.05 --rays 16 -q -o " + path("keep.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_TRUE(fs::exists(path("keep.h5.tmp.notes")));
  EXPECT_TRUE(fs::exists(path("keep.h5.tmp.123.0000abcd")));
  EXPECT_FALSE(fs::exists(path("keep.h5.tmp.radiosity-9999999-0badcafe")));
  // The same for every writer: the picture, the scene's OBJ and MTL.
  for (const char* name : {"pic.png", "room.obj", "room.mtl"}) {
    std::ofstream(path(std::string(name) + ".tmp.mine")) << "a user's";
    std::ofstream(path(std::string(name) + ".tmp.radiosity-9999999-0badcafe")) << "stale";
  }
  ASSERT_EQ(
      radiosity(1, "render " + path("keep.h5") + " --width 32 --height 32 -o " + path("pic.png"))
          .exitCode,
      0);
  ASSERT_EQ(radiosity(1, "scene cornell -o " + path("room.obj")).exitCode, 0);
  for (const char* name : {"pic.png", "room.obj", "room.mtl"}) {
    EXPECT_TRUE(fs::exists(path(std::string(name) + ".tmp.mine"))) << name;
    EXPECT_FALSE(fs::exists(path(std::string(name) + ".tmp.radiosity-9999999-0badcafe"))) << name;
  }
}

// A PETSc option no part of the run asked for (misspelt, or for a solver that did not run) is
// named in a warning; one that was used is not.
TEST_F(EndToEnd, UnusedPetscOptionsAreWarnedAbout) {
  ProgramRun run = radiosity(2, "solve builtin:box --max-area 0.05 --rays 16 -q -o " +
                                    path("box.h5") + " -ksp_typo 3 -ksp_monitor_short");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("PETSc option -ksp_typo was not used"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("-ksp_monitor_short was not used"), std::string::npos) << run.output;
}

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
  std::ofstream(path("job.toml")) << "# a job\n[solve]\nrays = 16\nsolver = 'jacobi'\n"
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

// `radiosity scene` converts any scene to the HDF5 scene file, which every rank then reads in
// parallel: a two-rank solve from it gives the result of a solve from the OBJ, bit for bit.
TEST_F(EndToEnd, SceneConvertsToHdf5AndSolvesAsTheObjDoes) {
  ASSERT_EQ(radiosity(1, "scene cornell -o " + path("c.obj")).exitCode, 0);
  const ProgramRun convert = radiosity(2, "scene " + path("c.obj") + " -o " + path("c.h5"));
  ASSERT_EQ(convert.exitCode, 0) << convert.output;
  EXPECT_NE(convert.output.find("scene: 78 triangles, 60 vertices"), std::string::npos)
      << convert.output;
  const std::string options = " --max-area 4000 --rays 64 -q -o ";
  const ProgramRun fromObj = radiosity(2, "solve " + path("c.obj") + options + path("obj.h5"));
  ASSERT_EQ(fromObj.exitCode, 0) << fromObj.output;
  const ProgramRun fromHdf5 = radiosity(2, "solve " + path("c.h5") + options + path("h5.h5"));
  ASSERT_EQ(fromHdf5.exitCode, 0) << fromHdf5.output;
  const Result a = readResult(path("obj.h5")), b = readResult(path("h5.h5"));
  ASSERT_EQ(a.mesh.triangleCount(), b.mesh.triangleCount());
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.mesh.sourceFace, b.mesh.sourceFace);
  EXPECT_EQ(a.mesh.reflectance, b.mesh.reflectance);
  EXPECT_EQ(a.mesh.emission, b.mesh.emission);
  EXPECT_EQ(a.radiosity, b.radiosity);
  EXPECT_EQ(a.irradiance, b.irradiance);

  const ProgramRun info = radiosity(1, "info " + path("c.h5"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("triangles: 78"), std::string::npos) << info.output;

  // A built-in scene keeps its length unit.
  ASSERT_EQ(radiosity(1, "scene builtin:cornell -o " + path("mm.h5")).exitCode, 0);
  const ProgramRun unit =
      radiosity(2, "solve " + path("mm.h5") + " --max-area 4000 --rays 16 -q -o " + path("u.h5"));
  ASSERT_EQ(unit.exitCode, 0) << unit.output;
  EXPECT_EQ(readResult(path("u.h5")).attributes.lengthUnit, "mm");

  // And back to OBJ, which gives the same mesh again.
  ASSERT_EQ(radiosity(2, "scene " + path("c.h5") + " -o " + path("again.obj")).exitCode, 0);
  const ProgramRun fromAgain = radiosity(2, "solve " + path("again.obj") + options + path("3.h5"));
  ASSERT_EQ(fromAgain.exitCode, 0) << fromAgain.output;
  EXPECT_EQ(readResult(path("3.h5")).radiosity, a.radiosity);
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

// Every solve writes the ParaView sidecar with its result; `radiosity xdmf` writes the same one
// again (for results of older versions), and a result named .xmf is refused.
TEST_F(EndToEnd, SolveWritesTheXdmfSidecarAndXdmfWritesItAgain) {
  const std::string out = path("c.h5"), sidecar = path("c.xmf");
  ASSERT_EQ(radiosity(2, "solve builtin:box --rays 16 -q -o " + out).exitCode, 0);
  const auto read = [](const std::string& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string written = read(sidecar);
  EXPECT_NE(written.find(">c.h5:/display/triangles<"), std::string::npos) << written;
  fs::remove(sidecar);
  ProgramRun again = radiosity(1, "xdmf " + out);
  ASSERT_EQ(again.exitCode, 0) << again.output;
  EXPECT_EQ(read(sidecar), written);
  fs::create_directories(path("views"));
  ASSERT_EQ(radiosity(1, "xdmf " + out + " -o " + path("views/c.xmf")).exitCode, 0);
  EXPECT_NE(read(path("views/c.xmf")).find(">../c.h5:/display/triangles<"), std::string::npos);

  // The result says what made it; --version says the same.
  const Result result = readResult(out);
  for (const char* name : {"radiosity", "petsc", "embree", "hdf5", "mpi"})
    EXPECT_FALSE(result.attributes.software.count(name) == 0 ||
                 result.attributes.software.at(name).empty())
        << name;
  EXPECT_EQ(result.attributes.software.at("radiosity").rfind("0.2.0 (git ", 0), 0u);
  ProgramRun version = radiosity(1, "--version");
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_NE(version.output.find("radiosity " + result.attributes.software.at("radiosity")),
            std::string::npos)
      << version.output;
  EXPECT_NE(version.output.find("petsc 3.18"), std::string::npos) << version.output;

  ProgramRun named = radiosity(1, "solve builtin:box --rays 16 -q -o " + path("r.xmf"));
  EXPECT_EQ(named.exitCode, 2);
  EXPECT_NE(named.output.find("name the result .h5"), std::string::npos) << named.output;
  ProgramRun notResult = radiosity(1, "xdmf " + path("views/c.xmf"));
  EXPECT_EQ(notResult.exitCode, 2) << notResult.output;  // it would overwrite its input
}

}  // namespace
}  // namespace radiosity
