// The program as a Unix tool: stdout carries what a command is for (a report, a JSON summary),
// stderr the log, -q leaves only warnings and errors, --json gives a document a script can read
// whatever happened, and --help fits the terminal.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "end_to_end_fixture.h"
#include "text_occurrences.h"

namespace radiosity::testing {
namespace {

using nlohmann::json;

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

class CommandLineRun : public EndToEnd {
 protected:
  SplitRun split(int ranks, const std::string& arguments) const {
    return runProgramSplit(ranks, arguments, path("out.txt"), path("err.txt"));
  }
};

// A finished solve with -q prints nothing at all; without it, the log is on stderr only.
TEST_F(CommandLineRun, QuietPrintsNothingButWarningsAndTheLogGoesToStderr) {
  SplitRun quiet = split(2, "solve builtin:box --rays 16 -q -o " + path("q.h5"));
  ASSERT_EQ(quiet.exitCode, 0) << quiet.err << quiet.out;
  EXPECT_EQ(quiet.out, "");
  EXPECT_EQ(quiet.err, "");
  SplitRun loud = split(2, "solve builtin:box --rays 16 -o " + path("l.h5"));
  ASSERT_EQ(loud.exitCode, 0) << loud.err;
  EXPECT_EQ(loud.out, "");
  EXPECT_NE(loud.err.find("wrote " + path("l.h5")), std::string::npos) << loud.err;
  // A warning still shows with -q: a PETSc option nothing used.
  SplitRun warned = split(1, "solve builtin:box --rays 16 -q -o " + path("w.h5") + " -ksp_typo 3");
  ASSERT_EQ(warned.exitCode, 0) << warned.err;
  EXPECT_NE(warned.err.find("warning: PETSc option -ksp_typo"), std::string::npos) << warned.err;
  // -q for the other commands: info keeps its description on stdout, verify its verdict.
  SplitRun info = split(1, "info " + path("q.h5") + " -q");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("summary:"), std::string::npos);
  EXPECT_EQ(info.err, "");
  SplitRun verify = split(2, "verify " + path("q.h5") + " --patches 20 --paths 64 --tol 1 -q");
  ASSERT_EQ(verify.exitCode, 0) << verify.err;
  EXPECT_NE(verify.out.find("verify: passed"), std::string::npos) << verify.out;
  EXPECT_EQ(verify.err, "");
}

// info prints each figure once: the options the root attributes state (scene, seed, rays,
// ranks) and the solver's choice, software and solve figures are not listed again.
TEST_F(CommandLineRun, InfoPrintsEachFigureOnce) {
  ASSERT_EQ(
      split(1, "solve builtin:box --rays 24 --seed 7 --save-formfactors -q -o " + path("f.h5"))
          .exitCode,
      0);
  SplitRun info = split(1, "info " + path("f.h5"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const std::string& text = info.out;
  const auto count = [&](const std::string& what) { return testing::occurrences(text, what); };
  EXPECT_EQ(count("rays_per_patch = 24"), 1) << text;
  EXPECT_EQ(count("rays = 24"), 0) << text;
  EXPECT_EQ(count("seed = 7"), 1) << text;
  EXPECT_EQ(count("builtin:box"), 1) << text;
  EXPECT_EQ(count("save-formfactors = true"), 1) << text;  // (no attribute of its own)
  // Every text attribute's value, the solver's choice and the software included, once.
  const size_t from = text.find("attributes:\n"), to = text.find("summary:\n");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  std::istringstream lines(text.substr(from, to - from));
  int attributes = 0;
  for (std::string line; std::getline(lines, line);) {
    const size_t equals = line.find(" = ");
    if (line.rfind("  ", 0) != 0 || line.rfind("      ", 0) == 0 || equals == std::string::npos)
      continue;
    ++attributes;
    const std::string value = line.substr(equals + 3);
    // (texts: numbers may agree by chance, as a grey scene's channels do)
    if (value.front() == '"' && value.size() > 8) {
      EXPECT_EQ(count(value.substr(1, value.size() - 2)), 1) << line << "\n" << text;
    }
  }
  EXPECT_GT(attributes, 20) << text;
}

// solve --json: one document on stdout that agrees with the file written; the closed box's
// exact answer is within the error the document states.
TEST_F(CommandLineRun, SolveJsonDescribesTheRunAndAgreesWithTheFile) {
  SplitRun run = split(2, "solve builtin:box --rays 64 --json -o " + path("box.h5"));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json summary = json::parse(run.out);  // throws (and fails) unless stdout is one document
  EXPECT_EQ(summary["schema"], "radiosity.solve/1");
  EXPECT_EQ(summary["exit_code"], 0);
  EXPECT_EQ(summary["output"], path("box.h5"));
  EXPECT_EQ(summary["ranks"], 2);
  EXPECT_EQ(summary["rays_per_patch"], 64);
  const Result result = readResult(path("box.h5"));
  EXPECT_EQ(summary["patches"].get<int64_t>(), static_cast<int64_t>(result.radiosity.size()));
  EXPECT_EQ(summary["iterations"].get<int64_t>(), result.attributes.iterations);
  EXPECT_DOUBLE_EQ(summary["estimated_error"]["headline"].get<double>(),
                   figure(result, "error_estimate"));
  for (const char* stage : {"load", "mesh", "formfactors", "solve", "write"}) {
    EXPECT_TRUE(summary["stage_seconds"].contains(stage)) << stage;
    EXPECT_GT(summary["peak_memory_mb"][stage].get<double>(), 0) << stage;
  }
  for (const char* channel : {"red", "green", "blue"})
    EXPECT_GE(summary["estimated_error"]["B"][channel].get<double>(), 0) << channel;
  // The log went to stderr.
  EXPECT_NE(run.err.find("wrote"), std::string::npos);
}

// info --json of a result, of a checkpoint; a thermal result's figures are one "grey" channel.
TEST_F(CommandLineRun, InfoJsonListsDatasetsAttributesAndTheSummary) {
  ASSERT_EQ(radiosity(1, "solve builtin:box --rays 16 -q --checkpoint " + path("ck.h5") + " -o " +
                             path("box.h5"))
                .exitCode,
            0);
  SplitRun run = split(1, "info " + path("box.h5") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json info = json::parse(run.out);
  EXPECT_EQ(info["schema"], "radiosity.info/1");
  const Result result = readResult(path("box.h5"));
  const int64_t patches = static_cast<int64_t>(result.radiosity.size());
  EXPECT_EQ(info["summary"]["patches"].get<int64_t>(), patches);
  bool radiosityListed = false;
  for (const json& dataset : info["datasets"]) {
    if (dataset["name"] != "/patches/radiosity") continue;
    radiosityListed = true;
    EXPECT_EQ(dataset["type"], "float64");
    EXPECT_EQ(dataset["shape"], json::array({patches, 3}));
  }
  EXPECT_TRUE(radiosityListed) << run.out;
  EXPECT_EQ(info["attributes"]["seed"], 1);
  // The closed box: B = E/(1 - rho) everywhere; the mean B equals the file's.
  double mean = 0;
  for (const Rgb& b : result.radiosity) mean += b[0];
  mean /= static_cast<double>(patches);
  EXPECT_NEAR(info["summary"]["radiosity"]["mean"]["red"].get<double>(), mean, 1e-12 * mean);

  SplitRun checkpoint = split(1, "info " + path("ck.h5") + " --json");
  ASSERT_EQ(checkpoint.exitCode, 0) << checkpoint.err;
  const json saved = json::parse(checkpoint.out);
  EXPECT_EQ(saved["kind"], "radiosity checkpoint");
  EXPECT_FALSE(saved.contains("summary"));
}

// verify --json: the verdict in the document equals the exit code, and the figures are there.
TEST_F(CommandLineRun, VerifyJsonCarriesTheVerdict) {
  ASSERT_EQ(radiosity(2, "solve builtin:cornell --rays 64 -q -o " + path("c.h5")).exitCode, 0);
  for (const char* tol : {"1", "1e-9"}) {
    SplitRun run = split(
        2, "verify " + path("c.h5") + " --patches 20 --paths 256 --json --tol " + std::string(tol));
    const json report = json::parse(run.out);
    EXPECT_EQ(report["schema"], "radiosity.verify/1");
    EXPECT_EQ(report["exit_code"].get<int>(), run.exitCode) << tol;
    EXPECT_EQ(report["passed"].get<bool>(), run.exitCode == 0) << tol;
    EXPECT_EQ(run.exitCode, std::string(tol) == "1" ? 0 : 1) << run.err;
    EXPECT_EQ(report["sampled_patches"], 20);
    for (const char* channel : {"red", "green", "blue"}) {
      const json& measured = report["channels"][channel];
      EXPECT_EQ(measured["patches"], 20) << channel;
      EXPECT_GT(measured["measured_error"].get<double>(), 0) << channel;
      EXPECT_GE(measured["coverage"].get<double>(), 0) << channel;
    }
    // The human report went to stderr.
    EXPECT_NE(run.err.find("verify: "), std::string::npos);
  }
}

// A failing command with --json still prints a document with the exit code and the message.
TEST_F(CommandLineRun, AFailureWithJsonIsADocumentToo) {
  const std::string scene = path("broken.obj");
  writeText(scene, "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  SplitRun run = split(1, "solve " + scene + " --json -o " + path("x.h5"));
  EXPECT_EQ(run.exitCode, 3) << run.err;
  const json failure = json::parse(run.out);
  EXPECT_EQ(failure["schema"], "radiosity.failure/1");
  EXPECT_EQ(failure["command"], "solve");
  EXPECT_EQ(failure["exit_code"], 3);
  EXPECT_NE(failure["error"].get<std::string>().find("broken.obj:3"), std::string::npos)
      << failure.dump();
  EXPECT_NE(run.err.find("radiosity: error: "), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(path("x.h5")));
}

// --help fits 80 columns when stdout is not a terminal, and names the scene one way.
TEST_F(CommandLineRun, HelpFitsEightyColumnsAndNamesTheSceneOnce) {
  for (const char* command :
       {"", "solve", "render", "info", "xdmf", "scene", "study", "verify", "export"}) {
    SplitRun run = split(1, std::string(command) + " --help");
    ASSERT_EQ(run.exitCode, 0) << command << run.err;
    std::istringstream lines(run.out);
    int count = 0;
    for (std::string line; std::getline(lines, line); ++count)
      EXPECT_LE(line.size(), 80u) << command << ": " << line;
    EXPECT_GT(count, 3) << command;
  }
  SplitRun solve = split(1, "solve --help");
  EXPECT_NE(solve.out.find("SCENE"), std::string::npos);
  EXPECT_EQ(solve.out.find("--scene"), std::string::npos) << solve.out;
  // A job file's scene still counts, and the command line's wins over it.
  writeText(path("job.toml"), "scene = \"builtin:nothing-such\"\nrays = 16\nquiet = true\n");
  EXPECT_EQ(radiosity(1, "solve --config " + path("job.toml") + " builtin:box -o " + path("b.h5"))
                .exitCode,
            0);
  writeText(path("job2.toml"), "scene = \"builtin:box\"\nrays = 16\nquiet = true\n");
  EXPECT_EQ(radiosity(1, "solve --config " + path("job2.toml") + " -o " + path("b2.h5")).exitCode,
            0);
  ProgramRun none = radiosity(1, "solve --rays 16");
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_NE(none.output.find("no scene given"), std::string::npos) << none.output;
  // verify --paths: the range --help shows is the range taken.
  SplitRun verify = split(1, "verify --help");
  EXPECT_NE(verify.out.find("--paths INT:INT in [2 - "), std::string::npos) << verify.out;
}

// --log-file: the log, warnings and errors also go to a file (even with -q), appended run
// after run; a log file that is an input or another output is refused before it is opened.
TEST_F(CommandLineRun, LogFileKeepsTheLogRunAfterRun) {
  const std::string log = path("run.log");
  SplitRun quiet = split(2, "solve builtin:box --max-area 0.05 --rays 16 -q -o " + path("a.h5") +
                                " --log-file " + log);
  ASSERT_EQ(quiet.exitCode, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  const std::string first = readText(log);
  EXPECT_EQ(testing::occurrences(first, "radiosity solve, started "), 1) << first;
  EXPECT_EQ(testing::occurrences(first, "load: "), 1) << first;  // (held until the log opened)
  EXPECT_EQ(testing::occurrences(first, "log-file = " + log), 1) << first;
  EXPECT_EQ(testing::occurrences(first, "wrote " + path("a.h5")), 1) << first;
  // A second run appends, and its error is in the log as on stderr.
  writeText(path("bad.toml"), "emissivity = 0.5\n");
  SplitRun failed = split(1, "solve builtin:box --max-area 0.05 --rays 16 -q -o " + path("b.h5") +
                                 " --thermal " + path("bad.toml") + " --log-file " + log);
  EXPECT_EQ(failed.exitCode, 3) << failed.err;
  const std::string both = readText(log);
  EXPECT_EQ(both.rfind(first, 0), 0U) << both;
  EXPECT_EQ(testing::occurrences(both, "radiosity solve, started "), 2) << both;
  EXPECT_EQ(testing::occurrences(both, "radiosity: error: " + path("bad.toml") + ":1:"), 1) << both;
  // Not the result, nor the scene: refused (exit 2), neither touched.
  SplitRun same = split(1, "solve builtin:box --max-area 0.05 --rays 16 -q -o " + path("a.h5") +
                               " --log-file " + path("a.h5"));
  EXPECT_EQ(same.exitCode, 2) << same.err;
  EXPECT_NE(same.err.find("two outputs"), std::string::npos) << same.err;
  writeText(path("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  SplitRun input = split(1, "solve " + path("tri.obj") + " --rays 16 -q -o " + path("c.h5") +
                                " --log-file " + path("tri.obj"));
  EXPECT_EQ(input.exitCode, 2) << input.err;
  EXPECT_EQ(readText(path("tri.obj")), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

}  // namespace
}  // namespace radiosity::testing
