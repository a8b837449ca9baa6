// `radiosity render`, `info`, `scene`, `xdmf` and `export`: thin wrappers around io/ and render/.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/checkpoint.h"
#include "io/store/result.h"
#include "io/store/result_tables.h"
#include "io/store/scene_file.h"
#include "io/store/xdmf.h"
#include "jobs/commands.h"
#include "parallel/collective.h"
#include "render/render.h"
#include "run/output_paths.h"
#include "run/version.h"

namespace radiosity::jobs {

namespace {

std::optional<Vec3> toVec3(const std::vector<double>& xyz) {
  if (xyz.empty()) return std::nullopt;
  return Vec3{xyz[0], xyz[1], xyz[2]};
}

}  // namespace

int runRender(const RenderSettings& settings, const run::Console& console) {
  runCollectively(console.comm(), [&] { run::checkOutputs({settings.output}, {settings.input}); });
  Result result;
  runCollectively(console.comm(), [&] {
    result = readResult(settings.input);
    // (render checks it too, but knows no file name)
    if (const std::string problem = tracingProblem(result.mesh); !problem.empty())
      throw InputError(settings.input + ": cannot be traced: " + problem);
  });
  render::Options options;
  options.width = settings.width;
  options.height = settings.height;
  options.camera.eye = toVec3(settings.eye);
  options.camera.lookAt = toVec3(settings.lookAt);
  if (auto up = toVec3(settings.up)) options.camera.up = *up;
  options.camera.fovDegrees = settings.fov;
  options.exposureStops = settings.exposure;
  options.smooth = !settings.flat;
  options.falseColour = settings.falseColour;
  options.scale = settings.scale;
  render::renderImage(console.comm(), result, options, settings.output);
  console.info("wrote " + settings.output);
  return exit_code::kOk;
}

int runInfo(const std::string& path, const run::Console& console) {
  std::string text;
  runCollectively(console.comm(), [&] {
    if (!console.isRoot()) return;
    if (console.isJson())
      text = describeFileJson(path);
    else
      text = isCheckpoint(path)  ? describeCheckpoint(path)
             : isSceneFile(path) ? describeSceneFile(path)
                                 : describeResult(path);
  });
  if (console.isJson())
    console.json(text);
  else
    console.result(text);
  return exit_code::kOk;
}

int runScene(const SceneSettings& settings, const run::Console& console) {
  // A name without '.' or '/' before its ?parameters is a built-in scene (`cornell`,
  // `box?rho=0.9`), as before files were taken; anything else is a file.
  const std::string& name = settings.name;
  const std::string base = name.substr(0, name.find('?'));
  const bool builtin =
      name.rfind("builtin:", 0) == 0 || base.find_first_of("./") == std::string::npos;
  const std::string spec = builtin && name.rfind("builtin:", 0) != 0 ? "builtin:" + name : name;
  const bool toHdf5 = isHdf5Scene(settings.output);
  std::vector<std::string> outputs{settings.output};
  if (!toHdf5)
    outputs.push_back(std::filesystem::path(settings.output).replace_extension(".mtl").string());
  runCollectively(console.comm(), [&] {
    std::vector<std::string> inputs;
    if (!builtin) inputs = {spec, std::filesystem::path(spec).replace_extension(".mtl").string()};
    run::checkOutputs(outputs, inputs);
    if (toHdf5) run::checkMpiIoOutputs(outputs);
  });
  double started = MPI_Wtime();
  const Mesh mesh = loadScene(spec, console.comm());
  // The files the scene named (an OBJ's mtllib, whatever their names) are inputs too.
  runCollectively(console.comm(), [&] { run::checkOutputs(outputs, mesh.sourceFiles); });
  for (const std::string& warning : mesh.warnings) console.warn(warning);
  char line[160];
  std::snprintf(line, sizeof line, "scene: %lld triangles, %zu vertices, loaded in %.3g s",
                static_cast<long long>(mesh.triangleCount()), mesh.vertices.size(),
                run::slowestRank(console.comm(), MPI_Wtime() - started));
  console.info(line);
  started = MPI_Wtime();
  if (toHdf5) {
    writeSceneFile(console.comm(), settings.output, mesh, {spec, run::softwareVersions()});
  } else {
    runCollectively(console.comm(), [&] {
      if (console.isRoot()) writeSceneObj(mesh, settings.output);
    });
  }
  std::snprintf(line, sizeof line, " in %.3g s",
                run::slowestRank(console.comm(), MPI_Wtime() - started));
  console.info("wrote " + settings.output + line);
  return exit_code::kOk;
}

int runXdmf(const XdmfSettings& settings, const run::Console& console) {
  namespace fs = std::filesystem;
  const std::string output =
      settings.output.empty() ? xdmfPathFor(settings.input) : settings.output;
  bool smooth = true;
  runCollectively(console.comm(), [&] {
    run::checkOutputs({output}, {settings.input});
    if (!console.isRoot()) return;
    // The .h5 as seen from the sidecar's folder, so that the two can move together.
    const fs::path folder = fs::absolute(output).parent_path();
    const std::string reference = fs::absolute(settings.input).lexically_relative(folder).string();
    const XdmfSidecar sidecar = xdmfFor(settings.input, reference);
    smooth = sidecar.smooth;
    writeTextFilesAtomically({{output, sidecar.text}});
  });
  if (!smooth) {
    console.warn(settings.input +
                 " has no /display (written by an older version): the sidecar "
                 "shows B per patch (cell data); solve again for smooth shading");
  }
  console.info("wrote " + output);
  return exit_code::kOk;
}

int runExport(const ExportSettings& settings, const run::Console& console) {
  std::vector<std::string> outputs;
  for (const std::string* path :
       {&settings.viewFactors, &settings.groupsCsv, &settings.exchangeFactors})
    if (!path->empty()) outputs.push_back(*path);
  if (outputs.empty())
    throw Error(exit_code::kUsage,
                "export: nothing to write: give --view-factors FILE, --groups-csv FILE and/or "
                "--exchange-factors FILE");
  runCollectively(console.comm(), [&] {
    run::checkOutputs(outputs, {settings.input});
    if (!console.isRoot()) return;
    const Result result = readResult(settings.input);
    std::vector<std::pair<std::string, std::string>> files;
    if (!settings.viewFactors.empty()) {
      const std::string& path = settings.viewFactors;
      const bool csv = std::filesystem::path(path).extension() == ".csv";
      const std::string version = run::softwareVersions()["radiosity"];
      files.emplace_back(
          path, csv ? viewFactorCsv(result, settings.input)
                    : view3dText(result, version.substr(0, version.find(' ')), settings.input));
    }
    if (!settings.groupsCsv.empty())
      files.emplace_back(settings.groupsCsv, groupsCsv(result, settings.input));
    if (!settings.exchangeFactors.empty())
      files.emplace_back(settings.exchangeFactors, exchangeFactorCsv(result, settings.input));
    writeTextFilesAtomically(files);
  });
  for (const std::string& path : outputs) console.info("wrote " + path);
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
