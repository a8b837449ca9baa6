// The table of `solve`'s options (run/request_options.h) is the one place an option is declared:
// the command line, the settings echo, a checkpoint's identity, the result's attributes and
// solve's --json are made from it, and nothing reaches any of them that the table does not
// declare (or that is not one of the run's own figures, listed here).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/store/result.h"
#include "jobs/command_line.h"
#include "jobs_fixture.h"
#include "mpi_environment.h"
#include "run/checkpointing.h"
#include "run/derived_settings.h"
#include "run/request_options.h"
#include "run/solve_json.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace radiosity::jobs {
namespace {

std::set<std::string> declaredKeys() {
  std::set<std::string> declared;
  for (const run::RequestOption& option : run::requestOptions()) declared.insert(option.key());
  return declared;
}

// The names the result records options by: each entry's result key.
std::set<std::string> recordedKeys() {
  std::set<std::string> keys;
  for (const run::RequestOption& option : run::requestOptions())
    if (option.result.key != nullptr) keys.insert(option.result.key);
  return keys;
}

// A request with every option given that changes what is recorded.
run::SolveRequest everyOptionRequest() {
  std::vector<std::string> everyOption{"solve", "s.obj"};
  std::istringstream words(
      "--patches 9 --reciprocity --drop-threshold 0.1 --target-error 0.1 --refine-rounds 2 "
      "--max-patches 99 --balance count --contacts off --exact-rows off --formfactor-precision "
      "double --thermal t.toml --save-formfactors --solver cg --rtol 1e-5 --estimator mis "
      "--seed 18446744073709551615 --rays 77 --length-unit mm");
  for (std::string word; words >> word;) everyOption.push_back(word);
  return parse(everyOption).solve;
}

// Every option of `solve` is declared once: the command line has each entry of the table and
// nothing else, and no value reaches a checkpoint's identity or the result's options line unless
// an entry declares it.
TEST(SolveRequest, EveryOptionIsDeclaredInTheTable) {
  const std::set<std::string> declared = declaredKeys();
  CLI::App app;
  CommandLine parsed;
  declareCommandLine(app, parsed, 80);
  const std::set<std::string> programs{"help", "json", "config", "scene"};  // not the request's
  std::set<std::string> onCommandLine;
  for (const CLI::Option* option : app.get_subcommand("solve")->get_options()) {
    const std::string name = option->get_lnames().empty() ? "scene" : option->get_lnames()[0];
    onCommandLine.insert(name);
    if (programs.count(name) == 0) {
      EXPECT_EQ(declared.count(name), 1U) << "--" << name;
    }
  }
  for (const std::string& key : declared) {
    EXPECT_EQ(onCommandLine.count(key), 1U) << key;
  }

  const run::SolveRequest request = everyOptionRequest();
  run::RunPlan plan = run::initialPlan(request);
  plan.exactRows = plan.pairsOnce = plan.singlePrecision = true;
  const std::set<std::string> chosen{"ranks", "rows", "values"};  // what the run chose
  std::istringstream lines(run::describeSettings(request, plan, 1, 2));
  for (std::string line; std::getline(lines, line);) {
    const std::string key = line.substr(0, line.find(" = "));
    EXPECT_TRUE(declared.count(key) == 1 || chosen.count(key) == 1) << line;
  }
  const std::set<std::string> fingerprints{"scene", run::kMaterials, "mis light choice", "rows"};
  for (const auto& [key, value] : run::runIdentity(request, plan, testing::closedBox(1, 1), 1))
    EXPECT_TRUE(declared.count(key) == 1 || fingerprints.count(key) == 1) << key << " = " << value;
}

// The options line names the modes that are not the default by their table names.
TEST(SolveRequest, OptionsLineNamesModes) {
  run::SolveRequest settings = parse({"solve", "s.obj", "--balance", "count", "--contacts", "off",
                                      "--exact-rows", "off", "--solver", "gauss-seidel"})
                                   .solve;
  const std::string line = run::describeSettings(settings, run::initialPlan(settings), 1, 2);
  for (const std::string expected :
       {"\nbalance = count\n", "\ncontacts = off\n", "\nexact-rows = off\n",
        "\nsolver = gauss-seidel\n", "\nestimator = auto\n"})
    EXPECT_NE(line.find(expected), std::string::npos) << expected << " in " << line;
  const run::SolveRequest plain = parse({"solve", "s.obj"}).solve;
  const std::string defaults = run::describeSettings(plain, run::initialPlan(plain), 1, 2);
  for (const std::string absent : {"balance", "contacts", "exact-rows"})
    EXPECT_EQ(defaults.find(absent), std::string::npos) << absent << " in " << defaults;
}

// The result's attributes the run fills itself, not an option's value: the format, the solve's
// figures (iterations, residual, ...), the options line, the stage times, the solve's figures
// (solve_*), why the solver was chosen and what made the file (software_*).
bool isRunFigure(const std::string& name) {
  static const std::set<std::string> figures{"format_version", "ranks",         "left_out",
                                             "iterations",     "residual",      "converged",
                                             "options",        "solver_choice", "channels"};
  for (const char* family : {"time_", "solve_", "software_"})
    if (name.rfind(family, 0) == 0) return true;
  return figures.count(name) == 1;
}

// The run's values of the options, as the pipeline records them at the end.
ResultAttributes recordedAttributes(const run::SolveRequest& request, const run::RunPlan& plan) {
  ResultAttributes attributes;
  run::recordOptions({request, plan, 0.5, "mm", "cg"}, attributes);
  attributes.solverChoice = "named";
  attributes.stageSeconds = {{"solve", 1.0}};
  attributes.solveFigures = {{"error_estimate", 0.01}};
  attributes.software = {{"radiosity", "test"}};
  return attributes;
}

// The result records each option the table gives a result key, with the run's value, and
// nothing else of the options: every root attribute of a written result is a declared option
// or one of the run's own figures.
TEST(SolveRequest, TheResultRecordsOnlyDeclaredOptions) {
  const run::SolveRequest request = everyOptionRequest();
  const run::RunPlan plan = run::initialPlan(request);
  const ResultAttributes attributes = recordedAttributes(request, plan);
  EXPECT_EQ(attributes.scene, "s.obj");
  EXPECT_EQ(attributes.seed, 18446744073709551615ULL);
  EXPECT_EQ(attributes.raysPerPatch, plan.rays);
  EXPECT_EQ(attributes.raysPerPatch, 77);
  EXPECT_EQ(attributes.solver, "cg");  // the solver that solved
  EXPECT_EQ(attributes.lengthUnit, "mm");
  EXPECT_EQ(attributes.thermal, "t.toml");

  testing::SharedTempDir dir("request_options_test");
  const std::string path = (dir.path() / "r.h5").string();
  const Mesh patches = testing::closedBox(0.5, 1);
  LocalSolution solution;
  solution.radiosity = solution.irradiance =
      std::vector<Rgb>(static_cast<size_t>(patches.triangleCount()), Rgb{1, 1, 1});
  writeResult(MPI_COMM_WORLD, path, patches, solution, attributes);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  std::set<std::string> written;
  hsize_t index = 0;
  H5Aiterate2(
      file, H5_INDEX_NAME, H5_ITER_INC, &index,
      [](hid_t, const char* name, const H5A_info_t*, void* names) -> herr_t {
        static_cast<std::set<std::string>*>(names)->insert(name);
        return 0;
      },
      &written);
  H5Fclose(file);
  const std::set<std::string> recorded = recordedKeys();
  for (const std::string& name : written)
    EXPECT_TRUE(recorded.count(name) == 1 || isRunFigure(name)) << name;
  for (const std::string& key : recorded) EXPECT_EQ(written.count(key), 1U) << key;
}

// solve's --json shows the recorded options under the same keys, and its other keys are the
// run's own.
TEST(SolveRequest, TheJsonShowsOnlyDeclaredOptions) {
  const run::SolveRequest request = everyOptionRequest();
  const ResultAttributes attributes = recordedAttributes(request, run::initialPlan(request));
  const nlohmann::json summary =
      nlohmann::json::parse(run::solveJson({"r.h5", 12, &attributes, {}}));
  const std::set<std::string> runKeys{"schema",        "exit_code",         "output",
                                      "patches",       "channels",          "ranks",
                                      "iterations",    "residual",          "converged",
                                      "left_out",      "refinement_rounds", "estimated_error",
                                      "stage_seconds", "peak_memory_mb",    "solve_figures"};
  const std::set<std::string> recorded = recordedKeys();
  for (const auto& [key, value] : summary.items())
    EXPECT_TRUE(recorded.count(key) == 1 || runKeys.count(key) == 1) << key;
  for (const std::string& key : recorded) EXPECT_TRUE(summary.contains(key)) << key;
  EXPECT_EQ(summary["seed"].get<uint64_t>(), 18446744073709551615ULL);
  EXPECT_EQ(summary["thermal"], true);  // (the file is the result's; --json says whether)
  EXPECT_EQ(summary["solver"], "cg");
  EXPECT_EQ(summary["length_unit"], "mm");
}

}  // namespace
}  // namespace radiosity::jobs
