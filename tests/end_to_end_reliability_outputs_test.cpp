// Reliability suite (issue 25): outputs. A disk that fills up (or fails) under a collective HDF5
// write on 2 ranks ends every rank with one message and exit 1, no temporary and every existing
// output as it was, never a hang: through an LD_PRELOAD shim (tests/faults/disk_full.c) that
// fails the writes of one rank, and through a real small tmpfs where the test may mount one.
// Labels and length units of any size are written and read back, and a restart works after them.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "end_to_end_fixture.h"

namespace radiosity::testing {
namespace {

namespace fs = std::filesystem;

// A run that has not ended by then has hung (it used to spin for ever at 100 % CPU).
constexpr double kHangSeconds = 120;

int occurrences(const std::string& text, const std::string& what) {
  int count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

std::set<std::string> filesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

class WriteFailures : public EndToEnd {
 protected:
  void SetUp() override {
    EndToEnd::SetUp();
    full_ = dir_ / "full";
    fs::create_directories(full_);
  }

  // The shim's environment: rank `rank`'s writes under full/ fail past `bytes`; `kind` "full"
  // (ENOSPC, space allocated ahead counts) or "io" (EIO, every write counts).
  std::string fault(int rank, long long bytes, const std::string& kind = "full") const {
    return "LD_PRELOAD=" DISK_FULL_SHIM " RADIOSITY_FAULT_DIR=" + full_.string() +
           " RADIOSITY_FAULT_RANK=" + std::to_string(rank) +
           " RADIOSITY_FAULT_BYTES=" + std::to_string(bytes) + " RADIOSITY_FAULT_KIND=" + kind;
  }

  // Runs on 2 ranks; a run still going after kHangSeconds is killed and fails the test.
  ProgramRun runWithin(const std::string& arguments, const std::string& environment) const {
    const auto start = std::chrono::steady_clock::now();
    BackgroundRun run(2, arguments, path("log.txt"), environment);
    run.waitUntil([] { return false; }, kHangSeconds);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (seconds >= kHangSeconds) {
      ADD_FAILURE() << "hung: still running after " << kHangSeconds << " s: radiosity " << arguments
                    << "\n"
                    << readText(path("log.txt"));
      return {-2, readText(path("log.txt"))};
    }
    return run.wait();
  }

  // Exit 1 with one message saying what could not be written, the files in each folder as
  // before (no temporary) and each existing output's bytes unchanged.
  void expectCleanFailure(const ProgramRun& run, const std::string& what,
                          const std::set<std::string>& before,
                          const std::set<std::string>& fullBefore,
                          const std::vector<std::pair<std::string, std::string>>& unchanged) {
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_EQ(occurrences(run.output, "radiosity: error:"), 1) << run.output;
    EXPECT_NE(run.output.find("radiosity: error: " + what), std::string::npos) << run.output;
    std::set<std::string> after = filesIn(dir_);
    after.erase("log.txt");
    EXPECT_EQ(after, before) << "files beside the outputs changed (a temporary left?)";
    EXPECT_EQ(filesIn(full_), fullBefore) << "files on the full disk changed (a temporary left?)";
    for (const auto& [file, bytes] : unchanged) EXPECT_EQ(readText(file), bytes) << file;
  }

  // An existing output of that name, to be left as it was.
  std::string existing(const std::string& file) const {
    std::ofstream(file) << "an earlier output, not to be touched";
    return readText(file);
  }

  std::set<std::string> filesBeside() const {
    std::set<std::string> names = filesIn(dir_);
    names.erase("log.txt");
    return names;
  }

  fs::path full_;
};

const std::string kSolve = "solve builtin:cornell --patches 300 --rays 16 ";

// The result on a disk that is full: rank 0's reservation of its space fails, before any
// collective write.
TEST_F(WriteFailures, ResultOnAFullDisk) {
  const std::string out = (full_ / "r.h5").string(), old = existing(out);
  const auto before = filesBeside(), fullBefore = filesIn(full_);
  const ProgramRun run = runWithin(kSolve + "-o " + out, fault(0, 20000));
  expectCleanFailure(run, "cannot write result file " + out, before, fullBefore, {{out, old}});
  EXPECT_NE(run.output.find("No space left on device"), std::string::npos) << run.output;
}

// The result when rank 1's writes fail (a disk that fails it, or one that cannot allocate
// ahead), in the first dataset or further on: the ranks agree after each step.
TEST_F(WriteFailures, ResultWhenOneRanksWritesFail) {
  const std::string out = (full_ / "r.h5").string(), old = existing(out);
  for (const char* kind : {"full", "io"})
    for (long long bytes : {0LL, 3000LL, 20000LL}) {
      SCOPED_TRACE(std::string(kind) + " after " + std::to_string(bytes) + " bytes");
      const auto before = filesBeside(), fullBefore = filesIn(full_);
      const ProgramRun run = runWithin(kSolve + "-o " + out, fault(1, bytes, kind));
      expectCleanFailure(run, "cannot write result file " + out, before, fullBefore, {{out, old}});
    }
}

// The final checkpoint (staged with the result) on a full disk: neither is written.
TEST_F(WriteFailures, FinalCheckpointOnAFullDisk) {
  const std::string out = path("r.h5"), old = existing(out);
  const std::string checkpoint = (full_ / "c.h5").string();
  const auto before = filesBeside(), fullBefore = filesIn(full_);
  const ProgramRun run = runWithin(
      kSolve + "--checkpoint-every 0 --checkpoint " + checkpoint + " -o " + out, fault(0, 20000));
  expectCleanFailure(run, "cannot write checkpoint " + checkpoint, before, fullBefore,
                     {{out, old}});
}

// A periodic checkpoint once the disk has filled up: the run stops there, and the checkpoint
// written before stays whole (a restart reads it).
TEST_F(WriteFailures, PeriodicCheckpointWhenTheDiskFillsUp) {
  const std::string checkpoint = (full_ / "c.h5").string();
  const std::string out = path("r.h5"), old = existing(out);
  // Each checkpoint takes ~0.5 MB ahead (the shim gives none back): two fit, the third not.
  const std::string options =
      "solve builtin:cornell --patches 600 --rays 64 --checkpoint " + checkpoint + " -o " + out;
  const auto before = filesBeside();
  const ProgramRun run = runWithin(options + " --checkpoint-every 0.001", fault(0, 1300000));
  expectCleanFailure(run, "cannot write checkpoint " + checkpoint, before, {"c.h5"}, {{out, old}});
  EXPECT_NE(run.output.find("checkpoint: wrote " + checkpoint), std::string::npos) << run.output;
  const ProgramRun info = radiosity(1, "info " + checkpoint);
  EXPECT_EQ(info.exitCode, 0) << info.output;
  const ProgramRun resumed = radiosity(2, options + " --restart " + checkpoint);
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
}

// The HDF5 scene output on a full disk, and when rank 1's writes fail.
TEST_F(WriteFailures, SceneFile) {
  const std::string out = (full_ / "s.h5").string(), old = existing(out);
  for (int rank : {0, 1}) {
    SCOPED_TRACE("failing rank " + std::to_string(rank));
    const auto before = filesBeside(), fullBefore = filesIn(full_);
    const ProgramRun run = runWithin("scene builtin:cornell -o " + out, fault(rank, 0));
    expectCleanFailure(run, "cannot write scene file " + out, before, fullBefore, {{out, old}});
    if (HasFailure()) return;
  }
}

// A result that cannot be written after the solve leaves the final checkpoint in place, and the
// restart it names writes the result.
TEST_F(WriteFailures, FailedResultKeepsTheFinalCheckpoint) {
  const std::string out = (full_ / "r.h5").string(), checkpoint = path("c.h5");
  const std::string options = kSolve + "--checkpoint " + checkpoint + " -o " + out;
  const ProgramRun run = runWithin(options, fault(0, 20000));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("run again with --restart " + checkpoint), std::string::npos)
      << run.output;
  EXPECT_EQ(filesIn(full_), std::set<std::string>{}) << "a temporary left";
  EXPECT_EQ(filesBeside(), (std::set<std::string>{"c.h5", "full"})) << "a temporary left";
  const ProgramRun resumed = radiosity(2, options + " --restart " + checkpoint);
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_TRUE(fs::exists(out));
}

// A rank killed while the result is written (after the solve) leaves the final checkpoint in
// place, and the restart writes the result.
TEST_F(WriteFailures, KilledWhileWritingTheResultKeepsTheFinalCheckpoint) {
  const std::string out = path("r.h5"), checkpoint = path("c.h5");
  const std::string options = kSolve + "--checkpoint " + checkpoint + " -o " + out;
  {
    // The test hook stalls the ranks between the complete temporary and its rename.
    BackgroundRun run(2, options, path("log.txt"), "RADIOSITY_TEST_RESULT_STALL=60");
    const bool writing = run.waitUntil(
        [&] {
          for (const auto& entry : fs::directory_iterator(dir_))
            if (entry.path().filename().string().rfind("r.h5.", 0) == 0) return true;
          return false;
        },
        kHangSeconds);
    ASSERT_TRUE(writing) << readText(path("log.txt"));
    run.signal(SIGKILL, /*wholeGroup=*/true);
    run.wait();
  }
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(checkpoint));
  const ProgramRun resumed = radiosity(2, options + " --restart " + checkpoint);
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("stage done"), std::string::npos) << resumed.output;
  EXPECT_TRUE(fs::exists(out));
}

// A real file system that is full (a 200 kB tmpfs with 20 kB free), where the test may mount
// one (root, and mount permitted); skipped with a message otherwise.
TEST_F(WriteFailures, RealFullTmpfs) {
  if (::mount("tmpfs", full_.c_str(), "tmpfs", 0, "size=200k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                 << "): the LD_PRELOAD cases stand for it";
  struct Unmount {
    std::string dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{full_.string()};
  {
    std::ofstream fill(full_ / "fill");
    fill << std::string(180 * 1024, 'x');
  }
  const std::string out = (full_ / "r.h5").string(), old = existing(out);
  const std::string checkpoint = (full_ / "c.h5").string();
  const auto before = filesBeside(), fullBefore = filesIn(full_);
  ProgramRun run = runWithin(kSolve + "-o " + out, "");
  expectCleanFailure(run, "cannot write result file " + out, before, fullBefore, {{out, old}});
  if (HasFailure()) return;
  run = runWithin(kSolve + "--checkpoint " + checkpoint + " -o " + out, "");
  expectCleanFailure(run, "cannot write checkpoint " + checkpoint, before, fullBefore,
                     {{out, old}});
  if (HasFailure()) return;
  const std::string scene = (full_ / "s.h5").string();
  run = runWithin("scene builtin:cornell -o " + scene, "");
  expectCleanFailure(run, "cannot write scene file " + scene, before, fullBefore, {{out, old}});
}

// ---- Labels and length units of any size (HDF5 attributes were limited to 64 kB each) ----

// A closed unit box whose floor is cut into strips, each face its own OBJ group named by
// `name(i)`: 1,024 labels in all.
void writeLabelledBox(const std::string& objPath, std::string (*name)(int)) {
  constexpr int kLabels = 1024, kStrips = kLabels - 5;
  std::ofstream obj(objPath);
  std::ofstream(fs::path(objPath).replace_extension(".mtl"))
      << "newmtl white\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n";
  obj << "mtllib " << fs::path(objPath).replace_extension(".mtl").filename().string() << "\n";
  int vertices = 0, label = 0;
  auto quad = [&](std::vector<Vec3> corners, const char* material) {
    for (const Vec3& v : corners) obj << "v " << v.x << " " << v.y << " " << v.z << "\n";
    obj << "g " << name(label++) << "\nusemtl " << material << "\n";
    obj << "f " << vertices + 1 << " " << vertices + 2 << " " << vertices + 3 << "\n";
    obj << "f " << vertices + 1 << " " << vertices + 3 << " " << vertices + 4 << "\n";
    vertices += 4;
  };
  for (int i = 0; i < kStrips; ++i) {
    const double x0 = double(i) / kStrips, x1 = double(i + 1) / kStrips;
    quad({{x0, 0, 0}, {x0, 0, 1}, {x1, 0, 1}, {x1, 0, 0}}, "white");
  }
  quad({{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}, "light");
  quad({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, "white");
  quad({{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, "white");
  quad({{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, "white");
  quad({{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}, "white");
}

std::string eightyCharacters(int i) {
  char head[16];
  std::snprintf(head, sizeof head, "surface_%04d_", i);
  return head + std::string(66, 'x');
}

std::string oneVeryLong(int i) {
  return i == 3 ? "long_" + std::string(40 * 1024, 'y') : "surface_" + std::to_string(i);
}

class LongNames : public EndToEnd {
 protected:
  // Solves `scene` with a checkpoint, reads the result back, restarts from the checkpoint with
  // more rays; returns the result.
  Result solveAndRestart(const std::string& scene) {
    const std::string options = "solve " + scene + " --max-area 0.01 --rays 8 --checkpoint " +
                                path("c.h5") + " -o " + path("r.h5");
    ProgramRun run = radiosity(2, options);
    EXPECT_EQ(run.exitCode, 0) << run.output;
    // The space reserved ahead and not used is given back (du as ls, to the block).
    for (const char* file : {"r.h5", "c.h5"}) {
      struct stat status {};
      EXPECT_EQ(::stat(path(file).c_str(), &status), 0);
      EXPECT_LE(status.st_blocks * 512, status.st_size + 64 * 1024) << file;
    }
    Result result = readResult(path("r.h5"));
    run = radiosity(2, options + " --rays 12 --restart " + path("c.h5"));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    return result;
  }
};

TEST_F(LongNames, ThousandLabelsOfEightyCharacters) {
  writeLabelledBox(path("box.obj"), eightyCharacters);
  const Result result = solveAndRestart(path("box.obj"));
  ASSERT_EQ(result.groups.names.size(), 1024u);
  for (int i = 0; i < 1024; ++i)
    EXPECT_NE(result.groups.names[i].find(eightyCharacters(i)), std::string::npos)
        << result.groups.names[i];
  // The HDF5 scene file keeps them too.
  const ProgramRun run = radiosity(2, "scene " + path("box.obj") + " -o " + path("box.h5"));
  EXPECT_EQ(run.exitCode, 0) << run.output;
  const ProgramRun solved = radiosity(
      2, "solve " + path("box.h5") + " --max-area 0.01 --rays 8 -o " + path("from_scene.h5"));
  EXPECT_EQ(solved.exitCode, 0) << solved.output;
  EXPECT_EQ(readResult(path("from_scene.h5")).groups.names, result.groups.names);
}

TEST_F(LongNames, OneLabelOfFortyKilobytes) {
  writeLabelledBox(path("box.obj"), oneVeryLong);
  const Result result = solveAndRestart(path("box.obj"));
  ASSERT_EQ(result.groups.names.size(), 1024u);
  EXPECT_NE(result.groups.names[3].find(oneVeryLong(3)), std::string::npos);
}

// A 64 kB length unit, as an HDF5 scene file may state it.
TEST_F(LongNames, LengthUnitOfSixtyFourKilobytes) {
  ProgramRun run = radiosity(1, "scene builtin:box -o " + path("box.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const std::string unit(64 * 1024, 'u');
  {
    const hid_t file = H5Fopen(path("box.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    if (H5Aexists(file, "length_unit") > 0) H5Adelete(file, "length_unit");
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, unit.size());
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate2(file, "length_unit", type, space, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(attribute, 0) << "the scene file cannot hold a 64 kB attribute";
    EXPECT_GE(H5Awrite(attribute, type, unit.data()), 0);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
    ASSERT_GE(H5Fclose(file), 0);
  }
  const Result result = solveAndRestart(path("box.h5"));
  EXPECT_EQ(result.attributes.lengthUnit, unit);
}

}  // namespace
}  // namespace radiosity::testing
