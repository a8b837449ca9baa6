// The options of `radiosity solve`, in the order --help lists them: the scene and its mesh, the
// form factors, the solve and the result, then how the run goes (checkpoints, rounds, ranks).
#include "core/enum_names.h"
#include "jobs/command_options.h"
#include "jobs/option_checks.h"

namespace radiosity::jobs {

namespace {

void addSceneAndMeshOptions(CLI::App* solve, run::SolveRequest& s) {
  solve->add_option(
      "SCENE", s.scene,
      "scene file (.obj, .ply, .off, .stl, .vs3, .h5) or builtin:NAME[?key=value&...]; "
      "in a --config job file: scene = \"...\"");
  // A job file's `scene` key, not shown: SCENE is the one way --help gives (the command line's
  // SCENE wins, as every option of the command line wins over the job file's).
  solve
      ->add_option_function<std::string>("--scene",
                                         [&s](const std::string& scene) {
                                           if (s.scene.empty()) s.scene = scene;
                                         })
      ->group("");
  solve->add_option("-o,--output", s.output,
                    "result file (HDF5) (default: the scene's name with .h5, .result.h5 for a "
                    "scene in HDF5, in the working directory)");
  addNumber(*solve, "--max-area", s.maxArea,
            "split triangles until each patch has at most this area (default: total area / 4000)",
            finiteIn(0, 1e300, true, " (leave it out for total area / 4000)"))
      ->default_str("");
  solve
      ->add_option("--patches", s.patches,
                   "refine to about this many patches (the area bound is chosen to reach it)")
      ->default_str("")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40))
      ->excludes("--max-area");
  solve->add_flag("--mesh-only", s.meshOnly,
                  "stop after meshing, write nothing (for timing the load and mesh stages)");
}

void addFormFactorOptions(CLI::App* solve, run::SolveRequest& s) {
  solve->add_option("--rays", s.raysPerPatch, "form-factor samples per patch")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 31));
  solve->add_option("--seed", s.seed, "sampling seed")->check(seedValue());
  std::vector<std::string> estimators{"auto"};
  for (const std::string& name : namesIn(formfactor::kEstimatorNames)) estimators.push_back(name);
  addChoice(
      *solve, "--estimator", estimators,
      [&s](const std::string& name) {
        s.estimator = valueNamed(formfactor::kEstimatorNames, name);  // none: auto
      },
      "form-factor estimator: auto (the default: mis where emitters are a small part of the "
      "scene, else hemisphere; the log says which and why), " +
          choicesDescribed(formfactor::kEstimatorNames))
      ->default_str("auto");
  solve->add_option("--threads", s.threads, "threads per rank for the form factors")
      ->check(CLI::Range(1, 1024));
  addChoice(
      *solve, "--contacts", namesIn(run::kContactsModes),
      [&s](const std::string& name) { s.cutContacts = *valueNamed(run::kContactsModes, name); },
      choicesDescribed(run::kContactsModes))
      ->default_str(nameIn(run::kContactsModes, s.cutContacts));
  addChoice(
      *solve, "--exact-rows", namesIn(run::kExactRowsModes),
      [&s](const std::string& name) {
        s.exactRowsAllowed = *valueNamed(run::kExactRowsModes, name);
      },
      choicesDescribed(run::kExactRowsModes))
      ->default_str(nameIn(run::kExactRowsModes, s.exactRowsAllowed));
  addChoice(
      *solve, "--formfactor-precision", namesIn(run::kValuePrecisions),
      [&s](const std::string& name) {
        s.valuePrecision = *valueNamed(run::kValuePrecisions, name);
      },
      "how F's values are stored: " + choicesDescribed(run::kValuePrecisions))
      ->default_str(nameIn(run::kValuePrecisions, s.valuePrecision));
}

void addSolveAndResultOptions(CLI::App* solve, run::SolveRequest& s) {
  addChoice(
      *solve, "--solver", namesIn(solve::kSolverNames),
      [&s](const std::string& name) { s.solver = valueNamed(solve::kSolverNames, name); },
      choicesDescribed(solve::kSolverNames, " | ", " | ") +
          " (default: chosen for the scene, and said which)");
  addNumber(*solve, "--rtol", s.rtol,
            "relative residual at which each channel's solve stops (default: where the solver's "
            "error bound is a tenth of the estimated sampling error)",
            finiteIn(0, 1, true))
      ->default_str("");
  solve->add_flag("--reciprocity", s.reciprocity,
                  "enforce reciprocity: symmetrise the estimates through A_i F_ij = A_j F_ji "
                  "(across ranks) and restore the row sums, reporting how far the raw estimates "
                  "were from it");
  addNumber(*solve, "--drop-threshold", s.dropThreshold,
            "drop form factors below this, then restore the row sums (default 0: keep all)",
            finiteIn(0, 1));
  solve
      ->add_option("--length-unit", s.lengthUnit,
                   "the scene's length unit (m, mm, ft, ...), recorded in the result's units "
                   "(default: the built-in scene's, none for a file)")
      ->check(lengthUnitName());
  solve->add_option("--thermal", s.thermal,
                    "thermal radiation exchange instead of lighting: a TOML file giving each "
                    "surface (by material or group name) an emissivity and a temperature (K) or "
                    "a net heat flux (W/m^2); lengths in metres unless --length-unit says "
                    "otherwise (docs/thermal.md)");
  solve->add_flag("--save-formfactors", s.saveFormFactors,
                  "also write the rows of F to the result file (/formfactors, CSR)");
}

// Checkpoints and stops, rounds of --target-error, the ranks' blocks, a restart.
void addRunOptions(CLI::App* solve, run::SolveRequest& s) {
  CLI::Option* checkpoint = solve->add_option(
      "--checkpoint", s.checkpoint,
      "write the run's state here periodically, on SIGTERM/SIGINT/SIGUSR1 (then exit "
      "75) and at the end");
  addNumber(*solve, "--checkpoint-every", s.checkpointEvery,
            "seconds between periodic checkpoints (0: only on a signal and at the end)",
            finiteIn(0, 1e9));
  addDuration(*solve, "--stop-after", s.stopAfter,
              "write the checkpoint and stop (exit 75) at the last safe point that leaves time "
              "for it before this long after the start: 5400, 90m, 3h50m, 03:50:00 (set it a few "
              "minutes below the job's time limit; needs --checkpoint)")
      ->needs(checkpoint);
  addNumber(*solve, "--target-error", s.targetError,
            "solve in rounds until the estimated error of B is below this (area-weighted RMS "
            "over the reflecting patches of each patch's error relative to its own B; the "
            "largest channel): each round reduces the larger part, the discretisation error by "
            "splitting the patches it comes from, the sampling error by more rays",
            finiteIn(0, 1e300, true))
      ->default_str("");
  solve
      ->add_option_function<std::string>(
          "--refine-rounds",
          [&s](const std::string& value) {
            int rounds = -1;  // "auto"; otherwise as the check read it (0x2, 1_0 alike)
            if (value != "auto") CLI::detail::lexical_cast(value, rounds);
            s.refineRounds = rounds;
          },
          "adaptive refinement rounds after the first solve: each splits the patches whose "
          "variation puts the most estimated error into the light the others gather, and "
          "solves again; auto (the default): one where the estimated error is mostly the "
          "mesh's, above 2 % (--target-error chooses its own)")
      ->default_str("auto")
      ->check(CLI::IsMember({"auto"}) | CLI::Range(0, 64));
  solve
      ->add_option(
          "--max-patches", s.maxPatches,
          "the most patches refinement rounds may make (default: as many as F at the "
          "rays asked fits in half the memory the job's nodes give it, a batch job's memory "
          "limit included; the log says how many)")
      ->default_str("")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  // The help names the modes in the order that explains them, auto last.
  addChoice(
      *solve, "--balance", namesIn(run::kBalanceModes),
      [&s](const std::string& name) { s.balance = *valueNamed(run::kBalanceModes, name); },
      "how the ranks' blocks of patches are cut: cost (by a short pilot's measured work per "
      "patch: rays' CPU time and nonzeros), count (equal numbers of patches) or auto (cost "
      "from 4 ranks up, where it pays for its pilot); the answer is the same either way")
      ->default_str(balanceModeName(s.balance));
  CLI::Option* restart =
      solve->add_option("--restart", s.restart,
                        "resume from this checkpoint (same scene and options; --rays may grow, "
                        "the materials may change: then its form factors serve and the solve "
                        "runs again), on any number of ranks");
  solve
      ->add_option("--formfactors-from", s.formfactorsFrom,
                   "reuse the complete form factors of this checkpoint (a run with --checkpoint: "
                   "same scene geometry and options, other materials, emission or --thermal "
                   "conditions allowed): no rays for F, no refinement rounds (docs/thermal.md)")
      ->excludes(restart)
      ->excludes("--target-error");
  addQuietFlag(*solve, s.quiet);
  solve->add_flag("-v,--verbose", s.verbose,
                  "the log adds the solver's and the error estimates' inner figures (the source "
                  "of the condition estimate, the calibration's scale factors)");
}

}  // namespace

void addSolveCommand(CLI::App& app, CommandLine& parsed) {
  run::SolveRequest& settings = parsed.solve;
  CLI::App* solve = app.add_subcommand("solve", "solve a scene and write the result (HDF5)");
  // A job file's value comes first on the expanded command line; the user's later one wins.
  solve->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  addSceneAndMeshOptions(solve, settings);
  addFormFactorOptions(solve, settings);
  addSolveAndResultOptions(solve, settings);
  addRunOptions(solve, settings);
  addJsonFlag(*solve, parsed.json);
  solve->add_option("--config", "TOML job file holding any of these options: `rays = 4096`");
}

}  // namespace radiosity::jobs
