// `radiosity render`, `info` and `scene`: thin wrappers around io/ and render/.
#include <iostream>

#include <filesystem>

#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/checkpoint.h"
#include "io/store/collective.h"
#include "io/store/result.h"
#include "jobs/commands.h"
#include "jobs/output_paths.h"
#include "render/render.h"

namespace radiosity::jobs {

namespace {

std::optional<Vec3> toVec3(const std::vector<double>& xyz) {
  if (xyz.empty()) return std::nullopt;
  return Vec3{xyz[0], xyz[1], xyz[2]};
}

}  // namespace

int runRender(const RenderSettings& settings, const Console& console) {
  runCollectively(console.comm(), [&] { checkOutputs({settings.output}, {settings.input}); });
  Result result;
  runCollectively(console.comm(), [&] { result = readResult(settings.input); });
  render::Options options;
  options.width = settings.width;
  options.height = settings.height;
  options.camera.eye = toVec3(settings.eye);
  options.camera.lookAt = toVec3(settings.lookAt);
  if (auto up = toVec3(settings.up)) options.camera.up = *up;
  options.camera.fovDegrees = settings.fov;
  options.exposureStops = settings.exposure;
  options.smooth = !settings.flat;
  render::renderToPng(console.comm(), result, options, settings.output);
  console.info("wrote " + settings.output);
  return exit_code::kOk;
}

int runInfo(const std::string& path, const Console& console) {
  std::string text;
  runCollectively(console.comm(), [&] {
    if (console.isRoot())
      text = isCheckpoint(path) ? describeCheckpoint(path) : describeResult(path);
  });
  console.info(text);
  return exit_code::kOk;
}

int runScene(const SceneSettings& settings, const Console& console) {
  std::string spec =
      settings.name.rfind("builtin:", 0) == 0 ? settings.name : "builtin:" + settings.name;
  runCollectively(console.comm(), [&] {
    checkOutputs({settings.output,
                  std::filesystem::path(settings.output).replace_extension(".mtl").string()},
                 {});
    Mesh mesh = loadScene(spec);
    if (console.isRoot()) writeSceneObj(mesh, settings.output);
  });
  console.info("wrote " + settings.output);
  return exit_code::kOk;
}

}  // namespace radiosity::jobs
