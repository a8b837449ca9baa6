// Every option of the program is declared here, once, with its check. CLI11 parses the command
// line; a --config job file (TOML, jobs/job_file.h: `rays = 4096`) is expanded into options
// first, and its unknown keys are refused. Estimator and solver names are checked against their
// lists here and turned into the enums once.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "formfactor/estimator.h"
#include "jobs/command_line.h"
#include "jobs/duration.h"
#include "jobs/job_file.h"
#include "jobs/version.h"
#include "solve/solver.h"

namespace radiosity::jobs {

namespace {

std::string compact(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// A list's default as it is typed (`16,64,256`), not as CLI11 shows it (`[16,64,256]`).
template <class T>
std::string typedList(const std::vector<T>& values) {
  std::ostringstream text;
  for (size_t i = 0; i < values.size(); ++i) text << (i ? "," : "") << values[i];
  return text.str();
}

// A finite number in [low, high] (`openLow`: above low). CLI11's own Range lets NaN through
// (every comparison with NaN is false) and prints its bounds in full, 300 digits for DBL_MAX.
CLI::Validator finiteIn(double low, double high, bool openLow = false,
                        const std::string& hint = "") {
  const std::string range = (openLow ? "(" : "[") + compact(low) + ", " + compact(high) + "]";
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(input.c_str(), &end);
        const std::string shown = input.size() > 40 ? input.substr(0, 40) + "..." : input;
        if (input.empty() || end != input.c_str() + input.size() || !std::isfinite(x) || x < low ||
            x > high || (openLow && x == low))
          return "'" + shown + "' is not a finite number in " + range + hint;
        return std::string();
      },
      "NUMBER in " + range);
}

// A unit name for the result's labels: a short word (m, mm, ft, au), not free text.
CLI::Validator lengthUnitName() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const bool word = !input.empty() && input.size() <= 16 &&
                          input.find_first_not_of(
                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTU"
                              "VWXYZ_") == std::string::npos;
        return word ? std::string() : "'" + input.substr(0, 40) + "' is not a unit name (letters)";
      },
      "UNIT");
}

// A duration as batch users write it (jobs/duration.h).
CLI::Validator durationValue() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        if (parseDuration(input)) return std::string();
        const std::string shown = input.size() > 40 ? input.substr(0, 40) + "..." : input;
        return "'" + shown +
               "' is not a duration: above 0 and at most 1000000000 seconds, written as "
               "5400, 90m, 1.5h, 3h50m, 03:50:00 or 1-12:00:00 (no exponents)";
      },
      "DURATION");
}

// A seed: a whole number in [0, 2^64 − 1], written in decimal (no sign, no exponent), so that
// -1 and 99999999999999999999 are refused instead of wrapping to 2^64 − 1.
CLI::Validator seedValue() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const std::string shown = input.size() > 40 ? input.substr(0, 40) + "..." : input;
        const bool digits = !input.empty() && input.size() <= 20 &&
                            input.find_first_not_of("0123456789") == std::string::npos;
        if (!digits || (input.size() == 20 && input > "18446744073709551615"))
          return "'" + shown + "' is not a whole number in [0, 18446744073709551615]";
        return std::string();
      },
      "UINT64");
}

void addSolveOptions(CLI::App& solve, SolveSettings& s) {
  // A job file's value comes first on the expanded command line; the user's later one wins.
  solve.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  solve
      .add_option("SCENE,--scene", s.scene,
                  "scene file (.obj, .ply, .off, .h5) or builtin:NAME[?key=value&...]")
      ->required();
  solve.add_option("-o,--output", s.output,
                   "result file (HDF5) (default: the scene's name with .h5, .result.h5 for a "
                   "scene in HDF5, in the working directory)");
  solve
      .add_option("--max-area", s.maxArea,
                  "split triangles until each patch has at most this area (default: total "
                  "area / 4000)")
      ->default_str("")
      ->check(finiteIn(0, 1e300, true, " (leave it out for total area / 4000)"));
  solve
      .add_option("--patches", s.patches,
                  "refine to about this many patches (the area bound is chosen to reach it)")
      ->default_str("")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40))
      ->excludes("--max-area");
  solve.add_flag("--mesh-only", s.meshOnly,
                 "stop after meshing, write nothing (for timing the load and mesh stages)");
  solve.add_option("--rays", s.raysPerPatch, "form-factor samples per patch")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 31));
  solve.add_option("--seed", s.seed, "sampling seed")->check(seedValue());
  solve
      .add_option_function<std::string>(
          "--estimator",
          [&s](const std::string& name) {
            s.estimator =
                name == "auto" ? std::nullopt : std::optional(formfactor::estimatorNamed(name));
          },
          "form-factor estimator: auto (the default: mis where emitters are a small "
          "part of the scene, else hemisphere; the log says which and why), hemisphere "
          "(1 ray per sample) or mis (hemisphere and emitter sampling by multiple "
          "importance sampling, 2 rays per sample)")
      ->default_str("auto")
      ->check(CLI::IsMember({"auto", "hemisphere", "mis"}));
  solve.add_option("--threads", s.threads, "threads per rank for the form factors")
      ->check(CLI::Range(1, 1024));
  solve
      .add_option_function<std::string>(
          "--contacts", [&s](const std::string& mode) { s.cutContacts = mode == "cut"; },
          "cut (the default: every triangle is cut along the lines where another touches, rests "
          "on or passes through it, before refinement, so that no patch straddles a lit part and "
          "a hidden one; patches that see nothing are left out of the solve) or off (the "
          "triangles as given)")
      ->default_str("cut")
      ->check(CLI::IsMember({"cut", "off"}));
  solve
      .add_option_function<std::string>(
          "--exact-rows", [&s](const std::string& mode) { s.exactRowsAllowed = mode == "auto"; },
          "auto (the default: rows of F by closed forms, without rays, where every pair of "
          "patches that face each other sees each other whole, i.e. a convex scene, and the "
          "patches are at most 8 x the rays per patch; the log says when) or off (always rays)")
      ->default_str("auto")
      ->check(CLI::IsMember({"auto", "off"}));
  solve
      .add_option_function<std::string>(
          "--solver", [&s](const std::string& name) { s.solver = solve::solverNamed(name); },
          "jacobi | gauss-seidel | gmres | cg | chebyshev (these two enforce reciprocity) | "
          "southwell (default: chosen for the scene, and said which)")
      ->check(CLI::IsMember(solve::solverNames()));
  solve
      .add_option("--rtol", s.rtol,
                  "relative residual at which each channel's solve stops (default: where the "
                  "solver's error bound is a tenth of the estimated sampling error)")
      ->default_str("")
      ->check(finiteIn(0, 1, true));
  solve.add_flag("--reciprocity", s.reciprocity,
                 "enforce reciprocity: symmetrise the estimates through A_i F_ij = A_j F_ji "
                 "(across ranks) and restore the row sums, reporting how far the raw estimates "
                 "were from it");
  solve
      .add_option("--drop-threshold", s.dropThreshold,
                  "drop form factors below this, then restore the row sums (default 0: keep all)")
      ->check(finiteIn(0, 1));
  solve
      .add_option("--length-unit", s.lengthUnit,
                  "the scene's length unit (m, mm, ft, ...), recorded in the result's units "
                  "(default: the built-in scene's, none for a file)")
      ->check(lengthUnitName());
  solve.add_flag("--save-formfactors", s.saveFormFactors,
                 "also write the rows of F to the result file (/formfactors, CSR)");
  CLI::Option* checkpoint = solve.add_option(
      "--checkpoint", s.checkpoint,
      "write the run's state here periodically, on SIGTERM/SIGINT/SIGUSR1 (then exit "
      "75) and at the end");
  solve
      .add_option("--checkpoint-every", s.checkpointEvery,
                  "seconds between periodic checkpoints (0: only on a signal and at the end)")
      ->check(finiteIn(0, 1e9));
  solve
      .add_option_function<std::string>(
          "--stop-after",
          [&s](const std::string& text) { s.stopAfter = parseDuration(text).value_or(0); },
          "write the checkpoint and stop (exit 75) at the last safe point that leaves time for it "
          "before this long after the start: 5400, 90m, 3h50m, 03:50:00 (set it a few minutes "
          "below the job's time limit; needs --checkpoint)")
      ->check(durationValue())
      ->needs(checkpoint);
  solve
      .add_option("--target-error", s.targetError,
                  "add rays (starting from --rays) until the estimated sampling error of B is "
                  "below this (area-weighted RMS over the reflecting patches of each patch's "
                  "error relative to its own B; the largest channel)")
      ->default_str("")
      ->check(finiteIn(0, 1e300, true));
  solve
      .add_option_function<std::string>(
          "--balance", [&s](const std::string& mode) { s.balance = mode; },
          "how the ranks' blocks of patches are cut: cost (by a short pilot's measured work per "
          "patch: rays' CPU time and nonzeros), count (equal numbers of patches) or auto (cost "
          "from 4 ranks up, where it pays for its pilot); the answer is the same either way")
      ->default_str("auto")
      ->check(CLI::IsMember({"auto", "cost", "count"}));
  solve.add_option("--restart", s.restart,
                   "resume from this checkpoint (same scene and options; --rays may grow), on "
                   "any number of ranks");
  solve.add_flag("-q,--quiet", s.quiet, "no progress lines");
}

void addRenderOptions(CLI::App& render, RenderSettings& s) {
  render.add_option("RESULT", s.input, "result file (HDF5)")->required();
  render.add_option("-o,--output", s.output, "image file (PNG)")->required();
  render.add_option("--width", s.width, "pixels")->check(CLI::Range(1, 16384));
  render.add_option("--height", s.height, "pixels")->check(CLI::Range(1, 16384));
  render
      .add_option("--eye", s.eye,
                  "camera position x,y,z (default: looking along +z at --look-at, far enough "
                  "back to see the whole scene)")
      ->default_str("")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e300, 1e300));
  render
      .add_option("--look-at", s.lookAt,
                  "point looked at x,y,z (default: the centre of the scene's bounding box)")
      ->default_str("")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e300, 1e300));
  render.add_option("--up", s.up, "up direction x,y,z")
      ->default_str("0,1,0")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e300, 1e300));
  render.add_option("--fov", s.fov, "vertical field of view, degrees")->check(finiteIn(1, 170));
  render.add_option("--exposure", s.exposure, "stops added to the automatic exposure")
      ->check(finiteIn(-100, 100));
  render.add_flag("--flat", s.flat, "flat patches instead of smooth shading");
}

// Replaces `--config FILE` by the options the job file holds, placed first so that options
// on the command line override them. Keys must name options of `command`.
// Where each option of the job file came from, so that a value CLI11 refuses is reported
// with the file and line (exit 3, bad input) rather than as a usage error without them.
struct JobFileOrigin {
  std::string file;
  std::map<std::string, std::pair<long, std::string>> lineOfKey;  ///< "--key" → line, value
  std::set<std::string> alsoOnCommandLine;                        ///< "--key"
};

std::vector<std::string> expandJobFile(const std::vector<std::string>& arguments,
                                       const CLI::App& command, JobFileOrigin& origin) {
  std::vector<std::string> expanded, rest;
  std::string jobFile;
  for (size_t i = 0; i < arguments.size(); ++i) {
    std::string named;
    if (arguments[i] == "--config" && i + 1 < arguments.size()) {
      named = arguments[++i];
    } else if (arguments[i].rfind("--config=", 0) == 0) {
      named = arguments[i].substr(9);
    } else {
      rest.push_back(arguments[i]);
      continue;
    }
    // One job file: a second would silently replace the first (they are not layered).
    if (!jobFile.empty())
      throw Error(exit_code::kUsage, "--config is given twice (" + shown(jobFile) + " and " +
                                         shown(named) + "): give one job file");
    jobFile = named;
  }
  if (jobFile.empty() || rest.empty() || rest[0] != command.get_name()) return arguments;
  expanded.push_back(rest[0]);
  origin.file = jobFile;
  for (const JobOption& option : readJobFile(jobFile)) {
    const CLI::Option* known = command.get_option_no_throw("--" + option.key);
    if (!known || option.key == "config" || option.key == "help") {
      throw InputError(jobFile, option.line, "unknown key '" + shown(option.key) + "'");
    }
    origin.lineOfKey["--" + option.key] = {option.line, option.value};
    if (known->get_expected_min() == 0) {  // a flag: true or false
      if (option.value == "true") {
        expanded.push_back("--" + option.key);
      } else if (option.value != "false") {
        throw InputError(
            jobFile, option.line,
            "'" + option.key + "' takes true or false, not '" + shown(option.value) + "'");
      }
      continue;
    }
    expanded.push_back("--" + option.key);
    expanded.push_back(option.value);
  }
  expanded.insert(expanded.end(), rest.begin() + 1, rest.end());
  return expanded;
}

}  // namespace

CommandLine parseCommandLine(const std::vector<std::string>& arguments, const Console& console) {
  CommandLine parsed;
  CLI::App app{
      "radiosity: diffuse global illumination on MPI ranks (PETSc options such as "
      "-ksp_type or -log_view go after the scene)",
      "radiosity"};
  app.require_subcommand(1);
  app.set_version_flag("--version", versionText());
  // --help shows each option's default after its type (`--rays INT=1024`). An option whose
  // default is worked out (for the scene, the camera) or which is off unless given shows none
  // there (default_str("")), rather than the 0 or [] that stands for it; its description says.
  app.option_defaults()->always_capture_default();

  SolveSettings& solveSettings = parsed.solve;
  CLI::App* solve = app.add_subcommand("solve", "solve a scene and write the result (HDF5)");
  addSolveOptions(*solve, solveSettings);
  solve->add_option("--config", "TOML job file holding any of these options: `rays = 4096`");

  RenderSettings& renderSettings = parsed.render;
  CLI::App* render = app.add_subcommand("render", "render a result file to a PNG picture");
  addRenderOptions(*render, renderSettings);

  std::string& infoPath = parsed.info;
  CLI::App* info = app.add_subcommand("info", "show what a result file holds");
  info->add_option("RESULT", infoPath, "result file")->required();

  XdmfSettings& xdmfSettings = parsed.xdmf;
  CLI::App* xdmf = app.add_subcommand(
      "xdmf",
      "write the XDMF sidecar (RESULT.xmf) that opens a result in ParaView or VisIt (every "
      "solve writes one; this is for older results)");
  xdmf->add_option("RESULT", xdmfSettings.input, "result file (HDF5)")->required();
  xdmf->add_option("-o,--output", xdmfSettings.output, "sidecar (default: RESULT with .xmf)");

  SceneSettings& sceneSettings = parsed.scene;
  CLI::App* scene = app.add_subcommand(
      "scene", "write a scene (built-in or a file) as OBJ+MTL or as an HDF5 scene file");
  scene
      ->add_option("SCENE", sceneSettings.name,
                   "built-in scene (cornell, box?rho=0.9, builtin:rooms?patches=1e6) or scene "
                   "file (.obj, .ply, .off, .h5)")
      ->required();
  scene
      ->add_option("-o,--output", sceneSettings.output,
                   "FILE.h5: HDF5 scene file (docs/scene-format.md), read fast by every rank; "
                   "any other name: OBJ with its .mtl beside it")
      ->required();

  StudySettings& studySettings = parsed.study;
  CLI::App* study = app.add_subcommand(
      "study", "error of B and H against an exact or reference answer, and run time, over a sweep");
  study->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  study->add_option("SCENE,--scene", studySettings.scene, "scene file or builtin:NAME")->required();
  study->add_option("-o,--output", studySettings.output, "CSV file, a row per setting")->required();
  study->add_option("--plot", studySettings.plot, "SVG file: error against time, and the solver");
  study->add_option("--reference", studySettings.reference,
                    "result file of a high-effort run of the same scene and mesh (default: the "
                    "scene's exact answer, for builtin box, sphere and plates)");
  study->add_option("--rays", studySettings.rays, "samples per patch to sweep, e.g. 16,64,256")
      ->default_str(typedList(studySettings.rays))
      ->delimiter(',')
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 31));
  study
      ->add_option_function<std::vector<std::string>>(
          "--estimator",
          [&studySettings](const std::vector<std::string>& names) {
            studySettings.estimators.clear();
            for (const std::string& name : names)
              studySettings.estimators.push_back(formfactor::estimatorNamed(name));
          },
          "estimators to sweep")
      ->default_str("hemisphere,mis")
      ->delimiter(',')
      ->check(CLI::IsMember({"hemisphere", "mis"}));
  study->add_option("--rtol", studySettings.rtols, "solver tolerances to sweep")
      ->default_str(typedList(studySettings.rtols))
      ->delimiter(',')
      ->check(finiteIn(0, 1, true));
  study
      ->add_option("--max-area", studySettings.maxAreas,
                   "patch area bounds to sweep (default: the solve's, total area / 4000)")
      ->default_str("")
      ->delimiter(',')
      ->check(finiteIn(0, 1e300, true));
  study
      ->add_option_function<std::string>(
          "--solver",
          [&studySettings](const std::string& name) {
            studySettings.solver = solve::solverNamed(name);
          },
          "the solver of every setting")
      ->default_str(solve::solverName(studySettings.solver))
      ->check(CLI::IsMember(solve::solverNames()));
  study->add_option("--seed", studySettings.seed, "sampling seed")->check(seedValue());
  study->add_option("--threads", studySettings.threads, "threads per rank")
      ->check(CLI::Range(1, 1024));
  study->add_flag("-q,--quiet", studySettings.quiet, "no line per setting");

  VerifySettings& verifySettings = parsed.verify;
  CLI::App* verify =
      app.add_subcommand("verify",
                         "path-trace patch-averaged B on a random sample of a result's patches and "
                         "print the result's measured error (independent of its form factors)");
  verify->add_option("RESULT", verifySettings.input, "result file (HDF5)")->required();
  verify->add_option("--patches", verifySettings.patches, "patches sampled (reflecting ones)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 30));
  verify->add_option("--paths", verifySettings.paths, "paths per sampled patch")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 30));
  verify
      ->add_option("--tol", verifySettings.tol,
                   "exit 1 when the measured RMS relative error of B is above this")
      ->check(finiteIn(0, 1e300, true));
  verify
      ->add_option("--max-bounces", verifySettings.maxBounces,
                   "a reference path is cut after this many bounces (its light beyond is lost; "
                   "only where reflectance is near 1 do paths get there)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 20));
  verify->add_option("--seed", verifySettings.seed, "sampling seed of the reference")
      ->check(seedValue());
  verify->add_option("--threads", verifySettings.threads, "threads per rank")
      ->check(CLI::Range(1, 1024));
  verify->add_option("--csv", verifySettings.csv, "CSV file, a row per sampled patch");

  // An unknown or missing command is named, with the list of commands (as registered above, so
  // that a new one is listed), not reported as "a subcommand is required".
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
    names.push_back(command->get_name());
  std::string commands;
  for (size_t i = 0; i < names.size(); ++i)
    commands += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  const std::string usage = ": the commands are " + commands + " (run with --help for usage)";
  auto isArgument = [&](const std::string& word) {
    return std::find(arguments.begin(), arguments.end(), word) != arguments.end();
  };
  const bool commandGiven = std::any_of(names.begin(), names.end(), isArgument);
  if (!arguments.empty() && !arguments[0].empty() && arguments[0][0] != '-' &&
      std::find(names.begin(), names.end(), arguments[0]) == names.end())
    throw Error(exit_code::kUsage, "unknown command '" + shown(arguments[0]) + "'" + usage);
  if (!commandGiven && !isArgument("-h") && !isArgument("--help") && !isArgument("--version"))
    throw Error(exit_code::kUsage, "no command given" + usage);
  JobFileOrigin origin;
  const std::vector<std::string> expanded = expandJobFile(arguments, *solve, origin);
  for (size_t i = 1; i < arguments.size(); ++i)
    origin.alsoOnCommandLine.insert(arguments[i].substr(0, arguments[i].find('=')));
  std::vector<std::string> reversed(expanded.rbegin(), expanded.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    std::ostringstream text;
    app.exit(e, text, text);
    console.info(text.str());
    return parsed;
  } catch (const CLI::CallForAllHelp& e) {
    std::ostringstream text;
    app.exit(e, text, text);
    console.info(text.str());
    return parsed;
  } catch (const CLI::CallForVersion& e) {
    console.info(versionText());
    return parsed;
  } catch (const CLI::ParseError& e) {
    const std::string message = e.what();
    // The job file's value is the culprit when the message names its option and, if the
    // command line gives that option too, quotes the job file's value.
    auto hasWord = [&](const std::string& word) {  // not part of a longer name or number
      auto inWord = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
      };
      for (size_t at = message.find(word); at != std::string::npos;
           at = message.find(word, at + 1)) {
        const size_t after = at + word.size();
        if ((at == 0 || !inWord(message[at - 1]) || word.front() == '-') &&
            (after == message.size() || !inWord(message[after])))
          return true;
      }
      return false;
    };
    for (const auto& [option, where] : origin.lineOfKey) {
      const auto& [line, value] = where;
      const bool ours = origin.alsoOnCommandLine.count(option) == 0 || hasWord(value);
      if (hasWord(option) && ours) throw InputError(origin.file, line, message);
    }
    throw Error(exit_code::kUsage, message + " (run with --help for usage)");
  }

  solveSettings.jobFile = origin.file;  // an input: never an output of the run
  for (const CLI::App* command : {solve, render, info, scene, study, verify, xdmf})
    if (*command) parsed.command = command->get_name();
  // (CLI11 requires one subcommand; this is only for safety)
  if (parsed.command.empty())
    throw Error(exit_code::kUsage, "no command (run with --help for usage)");
  return parsed;
}

int runCommandLine(const std::vector<std::string>& arguments, const Console& console) {
  const CommandLine parsed = parseCommandLine(arguments, console);
  if (parsed.command == "solve") return runSolve(parsed.solve, console);
  if (parsed.command == "render") return runRender(parsed.render, console);
  if (parsed.command == "info") return runInfo(parsed.info, console);
  if (parsed.command == "scene") return runScene(parsed.scene, console);
  if (parsed.command == "study") return runStudy(parsed.study, console);
  if (parsed.command == "verify") return runVerify(parsed.verify, console);
  if (parsed.command == "xdmf") return runXdmf(parsed.xdmf, console);
  return exit_code::kOk;  // --help or --version, printed
}

}  // namespace radiosity::jobs
