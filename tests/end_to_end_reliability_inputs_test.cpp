// Reliability suite (issue 25): inputs. Every file a command reads is an input the outputs must
// not be (job files, the MTL an OBJ names, whatever its name); only regular files are read (a
// FIFO would block for ever); one job file; no NUL in a job file's strings; names too long for
// the file system or MPI-IO refused before the work; ranks that would read different scene files
// read one; a reference result of another scene refused; two runs on the same names both end
// well, each with its own temporaries.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "end_to_end_fixture.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

namespace fs = std::filesystem;
using testing::closedBox;
using testing::EndToEnd;
using testing::parallelPlates;
using testing::ProgramRun;

const std::string kSmall = " --patches 300 --rays 16 -q";

// A run that cannot hang the suite: mpiexec is sent SIGTERM after `seconds`, which it forwards to
// the ranks (exit 124 from timeout), and SIGKILL 10 s later.
ProgramRun runWithin(int seconds, int ranks, const std::string& arguments, const std::string& log) {
  const std::string command = testing::programCommand(ranks, arguments, log, "",
                                                      "timeout -k 10 " + std::to_string(seconds));
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(log)};
}

// Files in the test's folder whose names hold ".tmp." (a temporary left behind).
std::vector<std::string> temporariesIn(const fs::path& folder) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().filename().string().find(".tmp.") != std::string::npos)
      found.push_back(entry.path().filename().string());
  return found;
}

// A job file that names itself as the output or the checkpoint would be replaced by HDF5.
TEST_F(EndToEnd, JobFileNamingItselfAsAnOutputIsRefused) {
  for (const char* key : {"output", "checkpoint"}) {
    const std::string job = path(std::string(key) + ".toml");
    const std::string text = "scene = \"builtin:cornell\"\npatches = 300\nrays = 16\n" +
                             std::string(key) + " = \"" + job + "\"\n";
    std::ofstream(job) << text;
    const std::string output = std::string(key) == "output" ? "" : " -o " + path("x.h5");
    ProgramRun run = radiosity(1, "solve --config " + job + output + " -q");
    EXPECT_EQ(run.exitCode, 2) << run.output;
    EXPECT_NE(run.output.find("is also an input"), std::string::npos) << run.output;
    EXPECT_EQ(testing::readText(job), text) << "the job file was overwritten";
  }
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

// The MTL an OBJ names (mtllib m.mtl, not plain.mtl) is an input: neither solve's result nor the
// MTL that `scene -o m.obj` writes beside its OBJ may replace it.
TEST_F(EndToEnd, TheMtlAnObjNamesIsAnInput) {
  const std::string mtl = "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n";
  std::ofstream(path("plain.obj")) << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\n"
                                      "f 1 2 3\n";
  std::ofstream(path("m.mtl")) << mtl;
  for (const std::string& arguments :
       {"solve " + path("plain.obj") + " --rays 16 -q -o " + path("m.mtl"),
        "solve " + path("plain.obj") + " --rays 16 -q --checkpoint " + path("m.mtl") + " -o " +
            path("r.h5"),
        "scene " + path("plain.obj") + " -o " + path("m.obj"),
        "study " + path("plain.obj") + " --rays 16 -o " + path("m.mtl")}) {
    ProgramRun run = radiosity(2, arguments);
    EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find("m.mtl: is also an input"), std::string::npos) << run.output;
    EXPECT_EQ(testing::readText(path("m.mtl")), mtl) << arguments;
  }
  for (const char* name : {"r.h5", "m.obj"}) EXPECT_FALSE(fs::exists(path(name))) << name;
}

// Output names whose temporary the file system or Open MPI's MPI-IO cannot take (an abort in
// OMPIO's lock-file buffer, or MPI_File_open failing after the whole solve), and directories on
// kernel file systems, are refused before any work; nothing is left behind.
TEST_F(EndToEnd, OutputNamesBeyondTheLimitsAreRefusedBeforeTheWork) {
  std::vector<std::string> names;
  for (size_t length : {213, 223}) names.push_back(std::string(length - 3, 'x') + ".h5");
  for (const std::string& name : names) {
    for (const std::string option : {" -o ", " --checkpoint "}) {
      const std::string arguments = "solve builtin:cornell" + kSmall + option + path(name) +
                                    (option == " -o " ? "" : " -o " + path("ok.h5"));
      ProgramRun run = runWithin(120, 1, arguments, path("log.txt"));
      EXPECT_EQ(run.exitCode, 2) << name.size() << option << "\n" << run.output;
      EXPECT_NE(run.output.find("too long"), std::string::npos) << run.output;
      EXPECT_EQ(run.output.find("form factors:"), std::string::npos) << "work was done first";
    }
  }
  // Relative names reach MPI-IO as given: its own limit, below the file system's.
  const std::string relative = std::string(200, 'y') + ".h5";
  ProgramRun refused =
      runWithin(120, 2, "solve builtin:cornell" + kSmall + " -o " + relative, path("log.txt"));
  EXPECT_EQ(refused.exitCode, 2) << refused.output;
  EXPECT_NE(refused.output.find("too long for MPI-IO"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(relative));
  for (const char* output : {"/proc/x.h5", "/sys/x.h5", "/dev/x.h5"}) {
    ProgramRun run = radiosity(1, "solve builtin:cornell" + kSmall + " -o " + output);
    EXPECT_EQ(run.exitCode, 2) << output << "\n" << run.output;
    EXPECT_NE(run.output.find("cannot write here"), std::string::npos) << run.output;
  }
  EXPECT_FALSE(fs::exists("/dev/x.h5"));
  EXPECT_TRUE(temporariesIn(dir_).empty());
  EXPECT_FALSE(fs::exists(path("ok.h5")));
}

// Only regular files are read: a FIFO where any file is read (opening it would block until
// someone writes) or a directory is refused at once, naming it (exit 3).
TEST_F(EndToEnd, OnlyRegularFilesAreRead) {
  ASSERT_EQ(radiosity(1, "solve builtin:cornell" + kSmall + " -o " + path("r.h5")).exitCode, 0);
  ASSERT_EQ(::mkfifo(path("pipe.h5").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(path("pipe.toml").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(path("pipe.obj").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(path("pipe.mtl").c_str(), 0644), 0);
  fs::create_directory(path("folder.h5"));
  std::ofstream(path("named.obj")) << "mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string pipe = path("pipe.h5");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"info " + pipe, pipe},
      {"verify " + pipe + " --patches 4 --paths 16", pipe},
      {"render " + pipe + " -o " + path("p.png"), pipe},
      {"xdmf " + pipe, pipe},
      {"solve " + pipe + " -q -o " + path("s.h5"), pipe},
      {"solve builtin:cornell" + kSmall + " --restart " + pipe + " -o " + path("s.h5"), pipe},
      {"study builtin:box --rays 16 --reference " + pipe + " -o " + path("s.csv"), pipe},
      {"solve --config " + path("pipe.toml"), path("pipe.toml")},
      {"solve " + path("pipe.obj") + " -q -o " + path("s.h5"), path("pipe.obj")},
      {"solve " + path("named.obj") + " -q -o " + path("s.h5"), "pipe.mtl"},
      {"info " + path("folder.h5"), path("folder.h5")},
  };
  for (const auto& [arguments, named] : cases) {
    ProgramRun run = runWithin(60, 1, arguments, path("log.txt"));
    EXPECT_EQ(run.exitCode, 3) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(named), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("only regular files are read"), std::string::npos) << run.output;
  }
  for (const char* name : {"p.png", "s.h5", "s.csv"}) EXPECT_FALSE(fs::exists(path(name))) << name;
}

// A dataset stored in an external raw file (here a FIFO) reads another file: refused, naming it.
TEST_F(EndToEnd, HdfDataOutsideTheFileIsRefused) {
  ASSERT_EQ(radiosity(1, "solve builtin:cornell" + kSmall + " -o " + path("r.h5")).exitCode, 0);
  ASSERT_EQ(::mkfifo(path("raw.bin").c_str(), 0644), 0);
  {
    const hid_t file = H5Fopen(path("r.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hsize_t count = 300;
    ASSERT_GE(H5Ldelete(file, "/patches/area", H5P_DEFAULT), 0);
    const hid_t creation = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_external(creation, path("raw.bin").c_str(), 0, count * sizeof(double));
    const hid_t space = H5Screate_simple(1, &count, nullptr);
    const hid_t dataset = H5Dcreate2(file, "/patches/area", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                     creation, H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Pclose(creation);
    H5Fclose(file);
  }
  for (const std::string command : {"info", "render", "verify"}) {
    const std::string output = command == "render"   ? " -o " + path("p.png")
                               : command == "verify" ? " --patches 4 --paths 16"
                                                     : "";
    ProgramRun run = runWithin(60, 1, command + " " + path("r.h5") + output, path("log.txt"));
    EXPECT_EQ(run.exitCode, 3) << command << "\n" << run.output;
    EXPECT_NE(run.output.find("stored in the external file"), std::string::npos) << run.output;
  }
}

// --config twice: the first would be ignored without a word.
TEST_F(EndToEnd, TwoJobFilesAreRefused) {
  std::ofstream(path("a.toml")) << "rays = 16\n";
  std::ofstream(path("b.toml")) << "patches = 300\n";
  ProgramRun run = radiosity(1, "solve builtin:cornell --config " + path("b.toml") + " --config " +
                                    path("a.toml") + " -o " + path("x.h5"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("--config is given twice"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

// A NUL in a job file's string cut the C name short: the result went straight to "a", past its
// temporary. Refused with the file and line, nothing written.
TEST_F(EndToEnd, NulInAJobFileStringIsRefused) {
  const std::string options = "patches = 300\nrays = 16\n";
  for (const std::string& text :
       {"scene = \"builtin:cornell\"\n" + options + "\noutput = \"" + path("a") + "\\u0000b.h5\"\n",
        "scene = \"builtin:cornell\"\n" + options + "\ncheckpoint = \"" + path("a") + "\\u0000\"\n",
        options + "\n\nscene = \"builtin:cornell\\u0000x\"\n"}) {
    std::ofstream(path("job.toml")) << text;
    ProgramRun run =
        runWithin(60, 2, "solve --config " + path("job.toml") + " -q", path("log.txt"));
    EXPECT_EQ(run.exitCode, 3) << text << "\n" << run.output;
    EXPECT_NE(run.output.find("job.toml:5: '"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("holds a NUL character"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(path("a"))) << text;
    EXPECT_TRUE(temporariesIn(dir_).empty());
  }
}

// Ranks that would read different scene files (one replaced while they start; here each rank
// started in its own folder, where the same name is another scene) read rank 0's: the answer is
// rank 0's scene, no hang.
TEST_F(EndToEnd, EveryRankSolvesTheSceneRankZeroRead) {
  fs::create_directory(path("a"));
  fs::create_directory(path("b"));
  writeSceneObj(closedBox(0.5, 1.0), path("a/s.obj"));
  Mesh other = parallelPlates(1, 1, 0.5);  // 4 triangles, not 12
  writeSceneObj(other, path("b/s.obj"));
  const std::string flags = std::string(MPIEXEC_PREFLAGS) + " " + RADIOSITY_BINARY + " " +
                            MPIEXEC_POSTFLAGS + " solve s.obj --rays 16 -q -o " + path("r.h5");
  const std::string command =
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
      "OMPI_MCA_rmaps_base_oversubscribe=1 timeout -k 10 60 " +
      std::string(MPIEXEC) + " " + MPIEXEC_NUMPROC_FLAG + " 1 --wdir " + path("a") + " " + flags +
      " : " + MPIEXEC_NUMPROC_FLAG + " 1 --wdir " + path("b") + " " + flags + " > " +
      path("log.txt") + " 2>&1";
  const int status = std::system(command.c_str());
  const std::string log = testing::readText(path("log.txt"));
  if (log.find("unrecognized") != std::string::npos) GTEST_SKIP() << "needs Open MPI's --wdir";
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
  const Result result = readResult(path("r.h5"));
  std::set<int64_t> faces(result.mesh.sourceFace.begin(), result.mesh.sourceFace.end());
  EXPECT_EQ(faces.size(), 12u) << "the box's 12 faces (rank 0's scene), not the plates' 4";
}

// A reference result of another scene with as many triangles (numbered alike) is refused,
// naming what differs, instead of giving a meaningless error.
TEST_F(EndToEnd, StudyReferenceOfAnotherSceneIsRefused) {
  Mesh box = closedBox(0.5, 0.0);
  box.emission[0] = box.emission[1] = {1, 1, 1};
  writeSceneObj(box, path("box.obj"));
  box.vertices[7].x += 0.3;  // the same triangles, numbered alike, another room
  writeSceneObj(box, path("wide.obj"));
  ASSERT_EQ(radiosity(1, "solve " + path("wide.obj") + " --max-area 10 --rays 16 -q -o " +
                             path("wide.h5"))
                .exitCode,
            0);
  ProgramRun run = radiosity(1, "study " + path("box.obj") +
                                    " --max-area 10 --rays 16 --estimator hemisphere "
                                    "--reference " +
                                    path("wide.h5") + " -o " + path("s.csv"));
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find("its mesh is not this study's"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("corner"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("s.csv")));
  // Its own scene's result is a reference.
  ASSERT_EQ(
      radiosity(1, "solve " + path("box.obj") + " --max-area 10 --rays 16 -q -o " + path("box.h5"))
          .exitCode,
      0);
  run = radiosity(1, "study " + path("box.obj") +
                         " --max-area 10 --rays 16 --estimator hemisphere --reference " +
                         path("box.h5") + " -o " + path("s.csv"));
  EXPECT_EQ(run.exitCode, 0) << run.output;
}

// Two runs on the same result and checkpoint names: each cleaned up the other's temporary as
// stale (cannot rename ... No such file or directory). Now both succeed, the file is one whole
// result, and no temporary is left.
TEST_F(EndToEnd, TwoRunsOnTheSameNamesBothSucceed) {
  const std::string arguments = "solve builtin:cornell --patches 300 --rays 64 -q -o " +
                                path("r.h5") + " --checkpoint " + path("c.h5") +
                                " --checkpoint-every 0.01";
  for (int round = 0; round < 2; ++round) {
    testing::BackgroundRun first(2, arguments, path("first.txt"));
    testing::BackgroundRun second(2, arguments, path("second.txt"));
    const ProgramRun a = first.wait(), b = second.wait();
    EXPECT_EQ(a.exitCode, 0) << a.output;
    EXPECT_EQ(b.exitCode, 0) << b.output;
    EXPECT_EQ(readResult(path("r.h5")).mesh.triangleCount(), 300);
    EXPECT_TRUE(temporariesIn(dir_).empty()) << temporariesIn(dir_).front();
  }
}

}  // namespace
}  // namespace radiosity
