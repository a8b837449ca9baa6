// Checkpoints reused: refused where they are damaged or of other options, extended with more
// rays (equal to a fresh run with that many), the rows rebuilt from the solver's matrix, and a
// job file that holds every option.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "checkpoint_run_fixture.h"
#include "hdf5_rewrite.h"
#include "io/store/checkpoint.h"
#include "io/store/checkpoint_format.h"
#include "io/store/hdf5_read.h"
#include "io/store/result.h"
#include "program_runner.h"

namespace radiosity {
namespace {

TEST_F(Checkpoints, CorruptedCheckpointsAndCheckpointsOfOtherOptionsAreRefused) {
  const std::string options = " builtin:cornell --max-area 8000 --rays 64 -q ";
  ASSERT_EQ(
      run(2, "solve" + options + "--checkpoint " + path("ck.h5") + " -o " + path("a.h5")).exitCode,
      0);
  // Other options: named, exit 3, no output.
  ProgramRun seed =
      run(2, "solve" + options + "--seed 2 --restart " + path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(seed.exitCode, 3) << seed.output;
  EXPECT_NE(seed.output.find("seed: 1 there, 2 now"), std::string::npos) << seed.output;
  ProgramRun scene = run(2, "solve builtin:cornell --max-area 4000 --rays 64 -q --restart " +
                                path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(scene.exitCode, 3) << scene.output;
  EXPECT_NE(scene.output.find("patches"), std::string::npos) << scene.output;
  ProgramRun fewer = run(2, "solve builtin:cornell --max-area 8000 --rays 32 -q --restart " +
                                path("ck.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(fewer.exitCode, 3) << fewer.output;
  EXPECT_NE(fewer.output.find("--rays"), std::string::npos) << fewer.output;
  EXPECT_FALSE(fs::exists(path("b.h5")));

  // Corrupted: bytes flipped in the middle of the file, where the rows are.
  std::string bytes = testing::readText(path("ck.h5"));
  for (size_t k = bytes.size() / 2; k < bytes.size() / 2 + 64; ++k)
    bytes[k] = static_cast<char>(~bytes[k]);
  std::ofstream(path("corrupt.h5"), std::ios::binary) << bytes;
  ProgramRun corrupt =
      run(2, "solve" + options + "--restart " + path("corrupt.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(corrupt.exitCode, 3) << corrupt.output;
  EXPECT_NE(corrupt.output.find("corrupt"), std::string::npos) << corrupt.output;
  // Truncated.
  std::ofstream(path("truncated.h5"), std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  ProgramRun truncated =
      run(2, "solve" + options + "--restart " + path("truncated.h5") + " -o " + path("b.h5"));
  EXPECT_EQ(truncated.exitCode, 3) << truncated.output;
  EXPECT_FALSE(fs::exists(path("b.h5")));
}

// A checkpoint whose refinement rounds do not replay on the scene's mesh (a merge at a vertex
// no split made, a mark past the mesh: the datasets themselves well formed, checksums right)
// is refused on restart: the round and the problem named, exit 3, no output.
TEST_F(Checkpoints, RefinementRoundsThatDoNotReplayAreRefused) {
  const std::string options =
      " builtin:cornell --max-area 4000 --rays 256 --refine-rounds 1 -q --checkpoint ";
  ASSERT_EQ(run(2, "solve" + options + path("ck.h5") + " -o " + path("a.h5")).exitCode, 0);
  fs::copy_file(path("ck.h5"), path("merge.h5"));
  testing::rewrite<int64_t>(path("merge.h5"), "/refinement/merged", H5T_NATIVE_INT64,
                            [](std::vector<int64_t>& v) { v.at(0) = 0; });  // a box corner
  fs::copy_file(path("ck.h5"), path("mark.h5"));
  testing::rewrite<int64_t>(path("mark.h5"), "/refinement/marked", H5T_NATIVE_INT64,
                            [](std::vector<int64_t>& v) { v.at(0) = 1000000; });
  for (const auto& [file, what] :
       {std::pair{"merge.h5", "is not the midpoint of a bisection to undo"},
        std::pair{"mark.h5", "splits patch 1000000"}}) {
    const ProgramRun restarted = run(2, "solve" + options + path(std::string(file) + ".ck") +
                                            " --restart " + path(file) + " -o " + path("b.h5"));
    EXPECT_EQ(restarted.exitCode, 3) << restarted.output;
    EXPECT_NE(restarted.output.find("corrupted checkpoint: refinement round 1"), std::string::npos)
        << restarted.output;
    EXPECT_NE(restarted.output.find(what), std::string::npos) << restarted.output;
    EXPECT_FALSE(fs::exists(path("b.h5")));
  }
}

// With F's values in double precision the extended rows are a fresh run's bit for bit; in
// single precision (the default here) the first rows' sums come back rounded, so F and B are a
// fresh run's to that rounding (2^-24 of each value).
TEST_F(Checkpoints, MoreRaysLaterEqualAFreshRunWithThatManyRays) {
  std::string scene = " builtin:cornell --max-area 4000 --rtol 1e-10 --save-formfactors ";
  {
    const std::string single = scene + "--formfactor-precision single ";
    ASSERT_EQ(run(2, "solve" + single + "--rays 64 --checkpoint " + path("s.ck.h5") + " -o " +
                         path("s64.h5"))
                  .exitCode,
              0);
    ProgramRun more = run(3, "solve" + single + "--rays 160 --restart " + path("s.ck.h5") + " -o " +
                                 path("smore.h5"));
    ASSERT_EQ(more.exitCode, 0) << more.output;
    ASSERT_EQ(run(2, "solve" + single + "--rays 160 -o " + path("sfresh.h5")).exitCode, 0);
    expectCloseAnswer(readResult(path("smore.h5")), readResult(path("sfresh.h5")), 0x1p-23, 1e-6);
  }
  scene += "--formfactor-precision double ";
  ASSERT_EQ(
      run(2, "solve" + scene + "--rays 64 --checkpoint " + path("ck.h5") + " -o " + path("64.h5"))
          .exitCode,
      0);
  EXPECT_EQ(stageOf(path("ck.h5")), "done");
  ProgramRun more = run(3, "solve" + scene + "--rays 160 --restart " + path("ck.h5") +
                               " --checkpoint " + path("ck.h5") + " -o " + path("more.h5"));
  ASSERT_EQ(more.exitCode, 0) << more.output;
  EXPECT_NE(more.output.find("given more samples"), std::string::npos) << more.output;
  ASSERT_EQ(run(2, "solve" + scene + "--rays 160 -o " + path("fresh.h5")).exitCode, 0);
  expectSameAnswer(readResult(path("more.h5")), readResult(path("fresh.h5")));
  // info shows what the checkpoint holds.
  ProgramRun info = run(1, "info " + path("ck.h5"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("stage: done"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("160"), std::string::npos) << info.output;
}

// F is stored once during the solve (PETSc's matrix) and its tally rebuilt from it for the
// checkpoints; a solver that works on the matrix in place (gauss-seidel) keeps a copy instead.
// The final checkpoints' rows must be the same tally either way, and the rebuilt one must serve
// a restart with more rays.
TEST_F(Checkpoints, TheRowsRebuiltFromTheSolversMatrixAreTheSampledRows) {
  // (in double precision: single-precision values give their sums back rounded,
  // single_precision_test)
  const std::string scene =
      " builtin:cornell --max-area 4000 --rtol 1e-10 --save-formfactors -q "
      "--formfactor-precision double ";
  for (const char* solver : {"gmres", "gauss-seidel"}) {
    const std::string name = solver;
    ProgramRun solved = run(2, "solve" + scene + "--rays 64 --solver " + name + " --checkpoint " +
                                   path(name + ".ck.h5") + " -o " + path(name + ".h5"));
    ASSERT_EQ(solved.exitCode, 0) << solved.output;
    EXPECT_EQ(stageOf(path(name + ".ck.h5")), "done");
  }
  // (read serially: MPI in this process would be inherited by the mpiexec it starts)
  auto dataset = [&](const std::string& file, const char* name) {
    h5::Handle opened = h5::openFile(path(file), "checkpoint");
    int64_t rows = -1;
    return h5::readDataset<int64_t>(opened.get(), path(file), name, H5T_NATIVE_INT64, 0, rows);
  };
  for (const char* name : {checkpoint_format::kSamples, checkpoint_format::kRowStart,
                           checkpoint_format::kColumn, checkpoint_format::kSum}) {
    const std::vector<int64_t> rebuilt = dataset("gmres.ck.h5", name),
                               kept = dataset("gauss-seidel.ck.h5", name);
    EXPECT_GT(kept.size(), 100u) << name;
    EXPECT_TRUE(rebuilt == kept) << name << " differs";
  }

  // (Checkpoints from inside the solve: SigtermInTheSolveThenRestartOnOneAndOnThreeRanks.)

  // More rays from the rebuilt rows equal a fresh run with that many.
  ProgramRun more = run(3, "solve" + scene + "--rays 96 --solver gmres --restart " +
                               path("gmres.ck.h5") + " -o " + path("more.h5"));
  ASSERT_EQ(more.exitCode, 0) << more.output;
  ASSERT_EQ(run(2, "solve" + scene + "--rays 96 --solver gmres -o " + path("fresh.h5")).exitCode,
            0);
  expectSameAnswer(readResult(path("more.h5")), readResult(path("fresh.h5")));
}

// A job file can hold every option, the scene and the checkpoint ones included; the plain
// mpirun template runs it to the end.
TEST_F(Checkpoints, AJobFileHoldsEveryOptionAndTheMpirunTemplateRunsIt) {
  std::ofstream(path("job.toml")) << "# a batch job\n[solve]\nscene = \"builtin:cornell\"\n"
                                  << "output = \"" << path("job.h5") << "\"\nmax-area = 8000\n"
                                  << "rays = 64\nsolver = \"cg\"\ncheckpoint = \""
                                  << path("job.ckpt.h5") << "\"\ncheckpoint-every = 0\n"
                                  << "quiet = true\n";
  ProgramRun direct = run(2, "solve --config " + path("job.toml"));
  ASSERT_EQ(direct.exitCode, 0) << direct.output;
  EXPECT_EQ(readResult(path("job.h5")).attributes.solver, "cg");
  EXPECT_EQ(stageOf(path("job.ckpt.h5")), "done");

  fs::remove(path("job.h5"));
  const std::string script = std::string(SOURCE_DIR) + "/jobs/templates/run_until_done.sh";
  const std::string command =
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
      "OMPI_MCA_rmaps_base_oversubscribe=1 NP=2 "
      "RADIOSITY=" RADIOSITY_BINARY " CHECKPOINT=" +
      path("template.ckpt.h5") + " bash " + script + " " + path("job.toml") + " > " +
      path("template.log") + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << testing::readText(path("template.log"));
  EXPECT_TRUE(fs::exists(path("job.h5")));
}

}  // namespace
}  // namespace radiosity
