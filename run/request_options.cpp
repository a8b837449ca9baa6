// The table of `radiosity solve`'s options (run/request_options.h), in --help's order.
#include "run/request_options.h"

#include <cstdio>
#include <sstream>

#include "core/enum_names.h"
#include "formfactor/estimator.h"
#include "solve/solver.h"

namespace radiosity::run {

namespace {

namespace attribute = result_format::attribute;

// A number as the echo writes it (6 significant digits) and as the identity keeps it (all 17).
std::string echoed(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}
std::string exact(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// The echo of an option shown only where it is given: `given` says whether it is.
template <class Show>
ShownValue when(bool (*given)(const SolveRequest&), Show show) {
  return [given, show](const RunShown& r) { return given(r.request) ? show(r) : std::string(); };
}

std::vector<std::string> estimatorChoices() {
  std::vector<std::string> names{"auto"};
  for (const std::string& name : namesIn(formfactor::kEstimatorNames)) names.push_back(name);
  return names;
}

// The record of an option kept in the attributes' `field` as `value` makes it; --json shows the
// field as it is.
template <class Field, class Value>
ResultRecord recordedAs(const char* key, Field ResultAttributes::*field, Value value) {
  return {key, [field, value](const RunShown& r, ResultAttributes& a) { a.*field = value(r); },
          [field](const ResultAttributes& a) -> RecordedValue { return a.*field; }};
}

std::string estimatorShown(const RunShown& r) {
  return r.plan.estimator ? formfactor::estimatorName(*r.plan.estimator) : "auto";
}
std::string solverShown(const RunShown& r) {
  return r.request.solver ? solve::solverName(*r.request.solver) : "auto";
}

constexpr double kMostPatches = static_cast<double>(int64_t{1} << 40);

std::vector<RequestOption> sceneAndMeshOptions() {
  return {
      {.name = "SCENE",
       .help = "scene file (.obj, .ply, .off, .stl, .vs3, .h5) or builtin:NAME[?key=value&...]; "
               "in a --config job file: scene = \"...\"",
       .kind = OptionKind::kScene,
       .field = &SolveRequest::scene,
       .echo = [](const RunShown& r) { return r.request.scene; },
       .result = recordedAs(attribute::kScene, &ResultAttributes::scene,
                            [](const RunShown& r) { return r.request.scene; })},
      {.name = "-o,--output",
       .help = "result file (HDF5) (default: the scene's name with .h5, .result.h5 for a scene "
               "in HDF5, in the working directory)",
       .field = &SolveRequest::output,
       .echo = [](const RunShown& r) { return r.request.output; }},
      {.name = "--max-area",
       .help = "split triangles until each patch has at most this area (default: total area / "
               "4000)",
       .kind = OptionKind::kNumber,
       .field = &SolveRequest::maxArea,
       .low = 0,
       .high = 1e300,
       .openLow = true,
       .hint = " (leave it out for total area / 4000)",
       .defaultShown = "",
       .echo = [](const RunShown& r) { return echoed(r.maxArea); },
       .identity = [](const RunShown& r) { return exact(r.maxArea); }},
      {.name = "--patches",
       .help = "refine to about this many patches (the area bound is chosen to reach it)",
       .kind = OptionKind::kWhole,
       .field = &SolveRequest::patches,
       .low = 1,
       .high = kMostPatches,
       .defaultShown = "",
       .excludes = {"--max-area"},
       .echo = when([](const SolveRequest& s) { return s.patches > 0; },
                    [](const RunShown& r) { return std::to_string(r.request.patches); }),
       .identity = [](const RunShown& r) { return std::to_string(r.request.patches); }},
      {.name = "--mesh-only",
       .help = "stop after meshing, write nothing (for timing the load and mesh stages)",
       .kind = OptionKind::kFlag,
       .field = &SolveRequest::meshOnly},
  };
}

std::vector<RequestOption> formFactorOptions() {
  return {
      {.name = "--rays",
       .help = "form-factor samples per patch",
       .kind = OptionKind::kWhole,
       .field = &SolveRequest::raysPerPatch,
       .low = 1,
       .high = static_cast<double>(int64_t{1} << 31),
       .echo = [](const RunShown& r) { return std::to_string(r.plan.rays); },
       .result = recordedAs(attribute::kRaysPerPatch, &ResultAttributes::raysPerPatch,
                            [](const RunShown& r) { return r.plan.rays; })},
      {.name = "--seed",
       .help = "sampling seed",
       .kind = OptionKind::kSeed,
       .field = &SolveRequest::seed,
       .echo = [](const RunShown& r) { return std::to_string(r.request.seed); },
       .identity = [](const RunShown& r) { return std::to_string(r.request.seed); },
       .result = recordedAs(attribute::kSeed, &ResultAttributes::seed,
                            [](const RunShown& r) { return r.request.seed; })},
      {.name = "--estimator",
       .help = "form-factor estimator: auto (the default: mis where emitters are a small part "
               "of the scene, else hemisphere; the log says which and why), " +
               choicesDescribed(formfactor::kEstimatorNames),
       .kind = OptionKind::kChoice,
       .defaultShown = "auto",
       .choices = estimatorChoices(),
       .choose =
           [](SolveRequest& s, const std::string& name) {
             s.estimator = valueNamed(formfactor::kEstimatorNames, name);  // none: auto
           },
       .echo = estimatorShown,
       .identity = estimatorShown},
      {.name = "--threads",
       .help = "threads per rank for the form factors",
       .kind = OptionKind::kWhole,
       .field = &SolveRequest::threads,
       .low = 1,
       .high = 1024,
       .echo = [](const RunShown& r) { return std::to_string(r.request.threads); }},
      {.name = "--contacts",
       .help = choicesDescribed(kContactsModes),
       .kind = OptionKind::kChoice,
       .defaultShown = nameIn(kContactsModes, SolveRequest().cutContacts),
       .choices = namesIn(kContactsModes),
       .choose = [](SolveRequest& s,
                    const std::string& name) { s.cutContacts = *valueNamed(kContactsModes, name); },
       .echo = when([](const SolveRequest& s) { return !s.cutContacts; },
                    [](const RunShown& r) {
                      return std::string(nameIn(kContactsModes, r.request.cutContacts));
                    }),
       .identity = [](const RunShown& r) -> std::string {
         return r.request.cutContacts ? "cut" : "not cut";
       }},
      {.name = "--exact-rows",
       .help = choicesDescribed(kExactRowsModes),
       .kind = OptionKind::kChoice,
       .defaultShown = nameIn(kExactRowsModes, SolveRequest().exactRowsAllowed),
       .choices = namesIn(kExactRowsModes),
       .choose =
           [](SolveRequest& s, const std::string& name) {
             s.exactRowsAllowed = *valueNamed(kExactRowsModes, name);
           },
       .echo = when([](const SolveRequest& s) { return !s.exactRowsAllowed; },
                    [](const RunShown& r) {
                      return std::string(nameIn(kExactRowsModes, r.request.exactRowsAllowed));
                    })},
      {.name = "--formfactor-precision",
       .help = "how F's values are stored: " + choicesDescribed(kValuePrecisions),
       .kind = OptionKind::kChoice,
       .defaultShown = nameIn(kValuePrecisions, SolveRequest().valuePrecision),
       .choices = namesIn(kValuePrecisions),
       .choose =
           [](SolveRequest& s, const std::string& name) {
             s.valuePrecision = *valueNamed(kValuePrecisions, name);
           },
       .echo = when([](const SolveRequest& s) { return s.valuePrecision != ValuePrecision::kAuto; },
                    [](const RunShown& r) {
                      return std::string(nameIn(kValuePrecisions, r.request.valuePrecision));
                    })},
  };
}

std::vector<RequestOption> solveAndResultOptions() {
  return {
      {.name = "--solver",
       .help = choicesDescribed(solve::kSolverNames, " | ", " | ") +
               " (default: chosen for the scene, and said which)",
       .kind = OptionKind::kChoice,
       .choices = namesIn(solve::kSolverNames),
       .choose = [](SolveRequest& s,
                    const std::string& name) { s.solver = valueNamed(solve::kSolverNames, name); },
       .echo = solverShown,
       .identity = solverShown,
       // (the solver that solved, the one named or the one chosen)
       .result = recordedAs(attribute::kSolver, &ResultAttributes::solver,
                            [](const RunShown& r) { return r.solverUsed; })},
      {.name = "--rtol",
       .help = "relative residual at which each channel's solve stops (default: where the "
               "solver's error bound is a tenth of the estimated sampling error)",
       .kind = OptionKind::kNumber,
       .field = &SolveRequest::rtol,
       .low = 0,
       .high = 1,
       .openLow = true,
       .defaultShown = "",
       .echo =
           [](const RunShown& r) { return r.request.rtol > 0 ? echoed(r.request.rtol) : "auto"; },
       .identity =
           [](const RunShown& r) { return r.request.rtol > 0 ? exact(r.request.rtol) : "auto"; }},
      {.name = "--reciprocity",
       .help = "enforce reciprocity: symmetrise the estimates through A_i F_ij = A_j F_ji "
               "(across ranks) and restore the row sums, reporting how far the raw estimates "
               "were from it",
       .kind = OptionKind::kFlag,
       .field = &SolveRequest::reciprocity,
       // (the plan's: a solver that needs it enforces it)
       .echo = [](const RunShown& r) { return r.plan.reciprocity ? "true" : ""; },
       .identity = [](const RunShown& r) { return r.plan.reciprocity ? "true" : "false"; }},
      {.name = "--drop-threshold",
       .help = "drop form factors below this, then restore the row sums (default 0: keep all)",
       .kind = OptionKind::kNumber,
       .field = &SolveRequest::dropThreshold,
       .low = 0,
       .high = 1,
       .echo = when([](const SolveRequest& s) { return s.dropThreshold > 0; },
                    [](const RunShown& r) { return echoed(r.request.dropThreshold); }),
       .identity = [](const RunShown& r) { return exact(r.request.dropThreshold); }},
      {.name = "--length-unit",
       .help = "the scene's length unit (m, mm, ft, ...), recorded in the result's units "
               "(default: the built-in scene's, none for a file)",
       .kind = OptionKind::kLengthUnit,
       .field = &SolveRequest::lengthUnit,
       .result = recordedAs(attribute::kLengthUnit, &ResultAttributes::lengthUnit,
                            [](const RunShown& r) { return r.lengthUnit; })},
      {.name = "--thermal",
       .help = "thermal radiation exchange instead of lighting: a TOML file giving each surface "
               "(by material or group name) an emissivity and a temperature (K) or a net heat "
               "flux (W/m^2); lengths in metres unless --length-unit says otherwise "
               "(docs/thermal.md)",
       .field = &SolveRequest::thermal,
       .echo = [](const RunShown& r) { return r.request.thermal; },
       // (the file in the result; whether the run was thermal in --json)
       .result = {attribute::kThermal,
                  [](const RunShown& r, ResultAttributes& a) { a.thermal = r.request.thermal; },
                  [](const ResultAttributes& a) -> RecordedValue { return !a.thermal.empty(); }}},
      {.name = "--save-formfactors",
       .help = "also write the rows of F to the result file (/formfactors, CSR)",
       .kind = OptionKind::kFlag,
       .field = &SolveRequest::saveFormFactors,
       .echo = [](const RunShown& r) { return r.request.saveFormFactors ? "true" : ""; }},
  };
}

// Checkpoints and stops, rounds of --target-error, the ranks' blocks, a restart, the log.
std::vector<RequestOption> runOptions() {
  return {
      {.name = "--checkpoint",
       .help = "write the run's state here periodically, on SIGTERM/SIGINT/SIGUSR1 (then exit "
               "75) and at the end",
       .field = &SolveRequest::checkpoint},
      {.name = "--checkpoint-every",
       .help = "seconds between periodic checkpoints (0: only on a signal and at the end)",
       .kind = OptionKind::kNumber,
       .field = &SolveRequest::checkpointEvery,
       .low = 0,
       .high = 1e9},
      {.name = "--stop-after",
       .help = "write the checkpoint and stop (exit 75) at the last safe point that leaves time "
               "for it before this long after the start: 5400, 90m, 3h50m, 03:50:00 (set it a "
               "few minutes below the job's time limit; needs --checkpoint)",
       .kind = OptionKind::kDuration,
       .field = &SolveRequest::stopAfter,
       .needs = {"--checkpoint"}},
      {.name = "--target-error",
       .help = "solve in rounds until the estimated error of B is below this (area-weighted RMS "
               "over the reflecting patches of each patch's error relative to its own B; the "
               "largest channel): each round reduces the larger part, the discretisation error "
               "by splitting the patches it comes from, the sampling error by more rays",
       .kind = OptionKind::kNumber,
       .field = &SolveRequest::targetError,
       .low = 0,
       .high = 1e300,
       .openLow = true,
       .defaultShown = "",
       .echo = when([](const SolveRequest& s) { return s.targetError > 0; },
                    [](const RunShown& r) { return echoed(r.request.targetError); })},
      {.name = "--refine-rounds",
       .help = "adaptive refinement rounds after the first solve: each splits the patches whose "
               "variation puts the most estimated error into the light the others gather, and "
               "solves again; auto (the default): one where the estimated error is mostly the "
               "mesh's, above 2 % (--target-error chooses its own)",
       .kind = OptionKind::kRounds,
       .field = &SolveRequest::refineRounds,
       .low = 0,
       .high = 64,
       .defaultShown = "auto",
       .echo = when([](const SolveRequest& s) { return s.refineRounds >= 0; },
                    [](const RunShown& r) { return std::to_string(r.request.refineRounds); })},
      {.name = "--max-patches",
       .help = "the most patches refinement rounds may make (default: as many as F at the rays "
               "asked fits in half the memory the job's nodes give it, a batch job's memory "
               "limit included; the log says how many)",
       .kind = OptionKind::kWhole,
       .field = &SolveRequest::maxPatches,
       .low = 1,
       .high = kMostPatches,
       .defaultShown = "",
       .echo = when([](const SolveRequest& s) { return s.maxPatches > 0; },
                    [](const RunShown& r) { return std::to_string(r.request.maxPatches); })},
      // The help names the modes in the order that explains them, auto last.
      {.name = "--balance",
       .help = "how the ranks' blocks of patches are cut: cost (by a short pilot's measured "
               "work per patch: rays' CPU time and nonzeros), count (equal numbers of patches) "
               "or auto (cost from 4 ranks up, where it pays for its pilot); the answer is the "
               "same either way",
       .kind = OptionKind::kChoice,
       .defaultShown = balanceModeName(SolveRequest().balance),
       .choices = namesIn(kBalanceModes),
       .choose = [](SolveRequest& s,
                    const std::string& name) { s.balance = *valueNamed(kBalanceModes, name); },
       .echo =
           when([](const SolveRequest& s) { return s.balance != BalanceMode::kAuto; },
                [](const RunShown& r) { return std::string(balanceModeName(r.request.balance)); })},
      {.name = "--restart",
       .help = "resume from this checkpoint (same scene and options; --rays may grow, the "
               "materials may change: then its form factors serve and the solve runs again), "
               "on any number of ranks",
       .field = &SolveRequest::restart},
      {.name = "--formfactors-from",
       .help = "reuse the complete form factors of this checkpoint (a run with --checkpoint: "
               "same scene geometry and options, other materials, emission or --thermal "
               "conditions allowed): no rays for F, no refinement rounds (docs/thermal.md)",
       .field = &SolveRequest::formfactorsFrom,
       .excludes = {"--restart", "--target-error"},
       .echo = [](const RunShown& r) { return r.request.formfactorsFrom; }},
      {.name = "--log-file",
       .help = "also append the log, warnings and errors to this file, flushed line by line "
               "(even with -q; a requeued job's runs follow each other)",
       .field = &SolveRequest::logFile,
       .echo = [](const RunShown& r) { return r.request.logFile; }},
      {.name = "-q,--quiet", .kind = OptionKind::kQuiet, .field = &SolveRequest::quiet},
      {.name = "-v,--verbose",
       .help = "the log adds the solver's and the error estimates' inner figures (the source of "
               "the condition estimate, the calibration's scale factors)",
       .kind = OptionKind::kFlag,
       .field = &SolveRequest::verbose},
  };
}

}  // namespace

std::string RequestOption::key() const {
  if (kind == OptionKind::kScene) return "scene";
  const size_t dashes = name.rfind("--");
  return dashes == std::string::npos ? name : name.substr(dashes + 2);
}

const std::vector<RequestOption>& requestOptions() {
  static const std::vector<RequestOption> table = [] {
    std::vector<RequestOption> all;
    for (auto part : {sceneAndMeshOptions, formFactorOptions, solveAndResultOptions, runOptions})
      for (RequestOption& option : part()) all.push_back(std::move(option));
    return all;
  }();
  return table;
}

void recordOptions(const RunShown& shown, ResultAttributes& attributes) {
  for (const RequestOption& option : requestOptions())
    if (option.result.record) option.result.record(shown, attributes);
}

std::vector<std::pair<std::string, RecordedValue>> recordedOptions(
    const ResultAttributes& attributes) {
  std::vector<std::pair<std::string, RecordedValue>> recorded;
  for (const RequestOption& option : requestOptions())
    if (option.result.key != nullptr)
      recorded.emplace_back(option.result.key, option.result.shown(attributes));
  return recorded;
}

}  // namespace radiosity::run
