// The options of the commands other than `solve` (jobs/solve_options.cpp): render, info, xdmf,
// scene, study and verify.
#include "jobs/command_options.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "jobs/option_checks.h"
#include "render/render.h"

namespace radiosity::jobs {

namespace {

// A point or direction x,y,z; `shownDefault` as --help shows it ("": worked out, none shown).
CLI::Option* addPoint(CLI::App& app, const std::string& name, std::vector<double>& point,
                      const std::string& help, const std::string& shownDefault) {
  return app.add_option(name, point, help)
      ->default_str(shownDefault)
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e300, 1e300));
}

// What a study sweeps: lists of rays, estimators, tolerances and area bounds.
void addSweepOptions(CLI::App& study, StudySettings& s) {
  study.add_option("--rays", s.rays, "samples per patch to sweep, e.g. 16,64,256")
      ->default_str(typedList(s.rays))
      ->delimiter(',')
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 31));
  std::vector<std::string> estimators;
  for (formfactor::Estimator estimator : s.estimators)
    estimators.push_back(formfactor::estimatorName(estimator));
  study
      .add_option_function<std::vector<std::string>>(
          "--estimator",
          [&s](const std::vector<std::string>& names) {
            s.estimators.clear();
            for (const std::string& name : names)
              s.estimators.push_back(formfactor::estimatorNamed(name));
          },
          "estimators to sweep")
      ->default_str(typedList(estimators))
      ->delimiter(',')
      ->check(CLI::IsMember(namesIn(formfactor::kEstimatorNames)));
  study.add_option("--rtol", s.rtols, "solver tolerances to sweep")
      ->default_str(typedList(s.rtols))
      ->delimiter(',')
      ->check(finiteIn(0, 1, true));
  study
      .add_option("--max-area", s.maxAreas,
                  "patch area bounds to sweep (default: the solve's, total area / 4000)")
      ->default_str("")
      ->delimiter(',')
      ->check(finiteIn(0, 1e300, true));
}

// The image's format is its name's: refused at once, not after the result is read.
CLI::Validator imageFileName() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        try {
          render::imageFormatOf(path);
          return "";
        } catch (const Error& e) {
          const std::string message = e.what();  // without the library's "render: "
          return message.substr(message.find(": ") + 2);
        }
      },
      "", "image file name");
}

// Options that make sense only together (checked once all are parsed).
void checkRenderOptions(const CLI::App& render, const RenderSettings& s) {
  const bool pfm = render::imageFormatOf(s.output) == render::ImageFormat::kPfm;
  const bool map = s.falseColour != render::FalseColour::kNone;
  if (map && pfm)
    throw CLI::ValidationError("--false-colour", "a false-colour map is a PNG: name it .png");
  if (render.count("--scale") && !map)
    throw CLI::ValidationError("--scale",
                               "only for a false-colour map: give --false-colour with a quantity");
  if (render.count("--exposure") && (pfm || map))
    throw CLI::ValidationError("--exposure", pfm ? "a .pfm holds the radiance itself, unexposed"
                                                 : "a false-colour map has its own scale");
}

}  // namespace

void addQuietFlag(CLI::App& command, bool& quiet) {
  command.add_flag("-q,--quiet", quiet,
                   "print only warnings and errors: no log, no progress (what the command is for "
                   "still goes to stdout)");
}

void addJsonFlag(CLI::App& command, bool& json) {
  command.add_flag("--json", json,
                   "print a JSON summary on stdout (docs/json-summaries.md); the log and the "
                   "report go to stderr");
}

namespace {

// -q and --json, for a command whose report a script may read.
void addQuietAndJsonFlags(CLI::App& command, CommandLine& parsed) {
  addQuietFlag(command, parsed.quiet);
  addJsonFlag(command, parsed.json);
}

// A command that reads a result file, named first (RESULT).
CLI::App* addResultCommand(CLI::App& app, const std::string& name, const std::string& description,
                           std::string& result, const std::string& help = "result file (HDF5)") {
  CLI::App* command = app.add_subcommand(name, description);
  command->add_option("RESULT", result, help)->required();
  return command;
}

}  // namespace

void addRenderCommand(CLI::App& app, CommandLine& parsed) {
  RenderSettings& s = parsed.render;
  CLI::App* render = addResultCommand(
      app, "render",
      "render a result file to a PNG picture, a linear HDR PFM or a false-colour map", s.input);
  render
      ->add_option("-o,--output", s.output,
                   "image file: .png (tone-mapped picture, or the --false-colour map) or .pfm "
                   "(linear radiance B/pi per pixel, float RGB, in the result's units)")
      ->required()
      ->check(imageFileName());
  render->add_option("--width", s.width, "pixels")->check(CLI::Range(1, 16384));
  render->add_option("--height", s.height, "pixels")->check(CLI::Range(1, 16384));
  addPoint(*render, "--eye", s.eye,
           "camera position x,y,z (default: looking along +z at --look-at, far enough back to "
           "see the whole scene)",
           "");
  addPoint(*render, "--look-at", s.lookAt,
           "point looked at x,y,z (default: the centre of the scene's bounding box)", "");
  addPoint(*render, "--up", s.up, "up direction x,y,z", "0,1,0");
  render->add_option("--fov", s.fov, "vertical field of view, degrees")->check(finiteIn(1, 170));
  render
      ->add_option("--exposure", s.exposure,
                   "stops added to the automatic exposure (of the PNG picture only)")
      ->check(finiteIn(-100, 100));
  render->add_flag("--flat", s.flat, "flat patches instead of smooth shading");
  addChoice(
      *render, "--false-colour", namesIn(render::kFalseColourNames),
      [&s](const std::string& name) {
        s.falseColour = *valueNamed(render::kFalseColourNames, name);
      },
      "a PNG map of the luminance of " + choicesDescribed(render::kFalseColourNames) +
          " in the result's units, with a legend, instead of the picture");
  addChoice(
      *render, "--scale", namesIn(render::kScaleNames),
      [&s](const std::string& name) { s.scale = *valueNamed(render::kScaleNames, name); },
      "the false-colour map's scale: " + choicesDescribed(render::kScaleNames))
      ->default_str(nameIn(render::kScaleNames, s.scale));
  addQuietFlag(*render, parsed.quiet);
  render->final_callback([render, &s] { checkRenderOptions(*render, s); });
}

void addXdmfCommand(CLI::App& app, CommandLine& parsed) {
  const std::string what =
      "write the XDMF sidecar (RESULT.xmf) that opens a result in ParaView or VisIt (every "
      "solve writes one; this is for older results)";
  CLI::App* xdmf = addResultCommand(app, "xdmf", what, parsed.xdmf.input);
  xdmf->add_option("-o,--output", parsed.xdmf.output, "sidecar (default: RESULT with .xmf)");
  addQuietFlag(*xdmf, parsed.quiet);
}

void addSceneCommand(CLI::App& app, CommandLine& parsed) {
  SceneSettings& s = parsed.scene;
  CLI::App* scene = app.add_subcommand(
      "scene", "write a scene (built-in or a file) as OBJ+MTL or as an HDF5 scene file");
  scene
      ->add_option("SCENE", s.name,
                   "built-in scene (cornell, box?rho=0.9, builtin:rooms?patches=1e6) or scene "
                   "file (.obj, .ply, .off, .stl, .vs3, .h5)")
      ->required();
  scene
      ->add_option("-o,--output", s.output,
                   "FILE.h5: HDF5 scene file (docs/scene-format.md), read fast by every rank; "
                   "any other name: OBJ with its .mtl beside it")
      ->required();
  addQuietFlag(*scene, parsed.quiet);
}

void addStudyCommand(CLI::App& app, CommandLine& parsed) {
  StudySettings& s = parsed.study;
  CLI::App* study = app.add_subcommand(
      "study", "error of B and H against an exact or reference answer, and run time, over a sweep");
  study->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  study->add_option("SCENE", s.scene, "scene file or builtin:NAME")->required();
  study->add_option("-o,--output", s.output, "CSV file, a row per setting")->required();
  study->add_option("--plot", s.plot, "SVG file: error against time, and the solver");
  study->add_option("--reference", s.reference,
                    "result file of a high-effort run of the same scene and mesh (default: the "
                    "scene's exact answer, for builtin box, sphere and plates)");
  addSweepOptions(*study, s);
  addChoice(
      *study, "--solver", namesIn(solve::kSolverNames),
      [&s](const std::string& name) { s.solver = solve::solverNamed(name); },
      "the solver of every setting")
      ->default_str(solve::solverName(s.solver));
  study->add_option("--seed", s.seed, "sampling seed")->check(seedValue());
  study->add_option("--threads", s.threads, "threads per rank")->check(CLI::Range(1, 1024));
  addQuietFlag(*study, s.quiet);
}

void addVerifyCommand(CLI::App& app, CommandLine& parsed) {
  VerifySettings& s = parsed.verify;
  CLI::App* verify =
      addResultCommand(app, "verify",
                       "path-trace patch-averaged B on a random sample of a result's patches and "
                       "print the result's measured error (independent of its form factors)",
                       s.input);
  verify->add_option("--patches", s.patches, "patches sampled (reflecting ones)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 30));
  // (two at least: the reference's own error needs two)
  verify->add_option("--paths", s.paths, "paths per sampled patch")
      ->check(CLI::Range(int64_t{2}, int64_t{1} << 30));
  verify
      ->add_option("--tol", s.tol, "exit 1 when the measured RMS relative error of B is above this")
      ->check(finiteIn(0, 1e300, true));
  verify
      ->add_option("--max-bounces", s.maxBounces,
                   "a reference path is cut after this many bounces (its light beyond is lost; "
                   "only where reflectance is near 1 do paths get there)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 20));
  verify->add_option("--seed", s.seed, "sampling seed of the reference")->check(seedValue());
  verify->add_option("--threads", s.threads, "threads per rank")->check(CLI::Range(1, 1024));
  verify->add_option("--csv", s.csv, "CSV file, a row per sampled patch");
  addQuietAndJsonFlags(*verify, parsed);
}

void addExportCommand(CLI::App& app, CommandLine& parsed) {
  ExportSettings& s = parsed.exportTables;
  CLI::App* exporter = addResultCommand(
      app, "export",
      "write a result's view factors between its groups (materials, groups, .vs3 surfaces, STL "
      "solids) for other tools: View3D's text layout or CSV with estimated errors",
      s.input);
  exporter->add_option(
      "--view-factors", s.viewFactors,
      "FILE: the group view factors in View3D's text output layout (its ViewHT reads it); a "
      "FILE ending in .csv: one row per pair with the estimated error");
  exporter->add_option(
      "--groups-csv", s.groupsCsv,
      "FILE: CSV, a row per group: area, patches, mean radiosity; heat rate, its error and "
      "mean temperature for a thermal run");
  exporter->add_option(
      "--exchange-factors", s.exchangeFactors,
      "FILE: CSV, a thermal result's exchange (Gebhart) factors, a row per pair of groups: the "
      "share of what one emits that the other absorbs after all reflections (needs its "
      "--save-formfactors)");
  addQuietFlag(*exporter, parsed.quiet);
}

void addInfoCommand(CLI::App& app, CommandLine& parsed) {
  CLI::App* info =
      addResultCommand(app, "info", "show what a result file holds", parsed.info, "result file");
  addQuietAndJsonFlags(*info, parsed);
}

}  // namespace radiosity::jobs
