// What used to end silently wrong, or late: a PETSc option that cannot be used, refused before
// any work; a PETSc flag before the scene; our other files given where a result is read; a
// --target-error run that cannot lower its error; a restart after a refinement round that raised
// the rays; a one-channel run's log.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "end_to_end_fixture.h"
#include "obj_room.h"

namespace radiosity::testing {
namespace {

namespace fs = std::filesystem;

// -pc_type bogus used to be found by the solve, after F was sampled: the form factors were lost
// with a raw PETSc trace and exit 1. Now: exit 2 before anything is done or written.
TEST_F(EndToEnd, PetscOptionsThatCannotBeUsedAreRefusedBeforeAnyWork) {
  for (const std::string& bad : {std::string("-pc_type bogus"), std::string("-ksp_type nonesuch"),
                                 std::string("-ksp_max_it many")}) {
    const ProgramRun run = radiosity(2, "solve builtin:cornell --checkpoint " + path("ck.h5") +
                                            " -o " + path("out.h5") + " " + bad);
    EXPECT_EQ(run.exitCode, 2) << bad << "\n" << run.output;
    EXPECT_NE(run.output.find("the PETSc options for the solve cannot be used"), std::string::npos)
        << run.output;
    EXPECT_EQ(run.output.find("load:"), std::string::npos) << "work was done: " << run.output;
    EXPECT_EQ(run.output.find("PETSC ERROR"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(path("ck.h5")));
    EXPECT_FALSE(fs::exists(path("out.h5")));
  }
  // Options PETSc knows still reach the solve.
  const ProgramRun good =
      radiosity(1, "solve builtin:box --rays 16 -o " + path("box.h5") + " -pc_type none");
  EXPECT_EQ(good.exitCode, 0) << good.output;
  EXPECT_EQ(good.output.find("was not used"), std::string::npos) << good.output;
}

// A PETSc flag written before the scene used to take the scene as its value ("no scene given").
TEST_F(EndToEnd, APetscFlagBeforeTheSceneLeavesTheSceneOurs) {
  const ProgramRun run =
      radiosity(1, "solve -ksp_converged_reason builtin:box --rays 16 -q -o " + path("b.h5"));
  EXPECT_EQ(run.exitCode, 0) << run.output;
  EXPECT_TRUE(fs::exists(path("b.h5")));
  writeBox(path("box.obj"), std::vector<Rgb>(6, Rgb{0.5, 0.5, 0.5}),
           {Rgb{1, 1, 1}, Rgb{}, Rgb{}, Rgb{}, Rgb{}, Rgb{}});
  const ProgramRun file = radiosity(
      1, "solve -ksp_converged_reason " + path("box.obj") + " --rays 16 -q -o " + path("f.h5"));
  EXPECT_EQ(file.exitCode, 0) << file.output;
  EXPECT_TRUE(fs::exists(path("f.h5")));
}

// render, verify and export given a checkpoint or a scene file say what the file is, not which
// result dataset it lacks.
TEST_F(EndToEnd, CommandsThatReadAResultNameTheOtherKindsOfOurFiles) {
  ASSERT_EQ(radiosity(1, "solve builtin:box --rays 16 -q --checkpoint " + path("ck.h5") + " -o " +
                             path("r.h5"))
                .exitCode,
            0);
  ASSERT_EQ(radiosity(1, "scene box -o " + path("scene.h5")).exitCode, 0);
  for (const std::string& command :
       {std::string("render FILE -o ") + path("x.png"), std::string("verify FILE"),
        std::string("export FILE --groups-csv ") + path("x.csv")}) {
    for (const auto& [file, kind] : {std::pair{path("ck.h5"), std::string("a checkpoint")},
                                     std::pair{path("scene.h5"), std::string("a scene file")}}) {
      std::string arguments = command;
      arguments.replace(arguments.find("FILE"), 4, file);
      const ProgramRun run = radiosity(1, arguments);
      EXPECT_EQ(run.exitCode, 3) << arguments << "\n" << run.output;
      EXPECT_NE(run.output.find(kind + ", not a result"), std::string::npos) << run.output;
      EXPECT_EQ(run.output.find("missing dataset"), std::string::npos) << run.output;
    }
  }
  EXPECT_FALSE(fs::exists(path("x.png")));
  EXPECT_FALSE(fs::exists(path("x.csv")));
}

// A small room whose error is the mesh's and cannot go below a floor: --target-error 1e-5 used to
// multiply the rays by 16 a round (16 -> 256 -> 4,096 -> 65,536 -> ...) with the estimate stuck
// and no round stopping it. Now the first refinement round that does not take a tenth off the
// estimate is the last, with a warning; the rays go no further than the mesh's error needs; and
// no round makes more patches than --max-patches.
TEST_F(EndToEnd, TargetErrorStopsWhereARoundDoesNotLowerTheEstimate) {
  writeRoomObj(
      path("room.obj"), path("room.mtl"), "newmtl lamp\nKd 0 0 0\nKe 20 20 20\n",
      {{"lamp",
        {{{1.75, 2.99, 1.75}, {2.25, 2.99, 1.75}, {2.25, 2.99, 2.25}, {1.75, 2.99, 2.25}}}}});
  const ProgramRun run = radiosity(
      2, "solve " + path("room.obj") +
             " --target-error 1e-5 --max-area 0.2 --max-patches 1300 --rays 16 -o " + path("t.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("did not lower the estimated discretisation error"), std::string::npos) << run.output;
  const Result result = readResult(path("t.h5"));
  EXPECT_LE(result.mesh.triangleCount(), 1300);
  EXPECT_LT(result.attributes.raysPerPatch, 16384) << run.output;
  EXPECT_LE(figure(result, "refinement_rounds"), 3) << run.output;
}

// A thermal run has one channel: its log never names red, green or blue, and q = 1 (a closed
// enclosure whose rows of given flux lose nothing) is said in words, not as "<= inf".
TEST_F(EndToEnd, AOneChannelRunsLogSpeaksOfOneChannel) {
  const ProgramRun run = radiosity(
      2, "solve " + std::string(SOURCE_DIR) + "/examples/furnace.obj --thermal " +
             std::string(SOURCE_DIR) + "/examples/furnace.toml --max-area 0.01 -o " + path("f.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  for (const char* colour : {"red", "green", "blue", "<= inf", "Hessenberg"})
    EXPECT_EQ(run.output.find(colour), std::string::npos) << colour << "\n" << run.output;
  EXPECT_NE(run.output.find("black patches (rho = 0) outside the iteration"), std::string::npos)
      << run.output;
  // -v gives the inner figures back.
  const ProgramRun verbose =
      radiosity(1, "solve builtin:box --rays 64 --solver gmres -v -o " + path("v.h5"));
  ASSERT_EQ(verbose.exitCode, 0) << verbose.output;
  EXPECT_NE(verbose.output.find("the condition estimate from"), std::string::npos)
      << verbose.output;
}

}  // namespace
}  // namespace radiosity::testing
