// libFuzzer target for the scene loaders: radiosity::loadScene() on OBJ (alone or with an MTL),
// PLY, OFF, STL, View3D's .vs3 and "builtin:" specs. Bad input must end in a radiosity::Error;
// anything else (a crash, a sanitizer report, another exception escaping, a hang) is a finding, and
// so is a mesh that passed loadScene() but breaks the invariants the later stages rely on.
//
// Input layout: the first byte chooses the format ('o' OBJ, 'm' OBJ + MTL, 'p' PLY, 'f' OFF,
// 's' STL, 'v' .vs3, 'b' built-in spec; any other byte picks one by its value modulo 7), the
// rest is the file.
// For OBJ + MTL the rest is split at the first "\n#MTL\n": the part before it is scene.obj (with
// "mtllib scene.mtl" put in front), the part after it is scene.mtl.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"

namespace {

namespace fs = std::filesystem;

enum class Format { kObj, kObjWithMtl, kPly, kOff, kStl, kVs3, kBuiltin };

Format formatOf(uint8_t selector) {
  switch (selector) {
    case 'o':
      return Format::kObj;
    case 'm':
      return Format::kObjWithMtl;
    case 'p':
      return Format::kPly;
    case 'f':
      return Format::kOff;
    case 's':
      return Format::kStl;
    case 'v':
      return Format::kVs3;
    case 'b':
      return Format::kBuiltin;
    default:
      break;
  }
  static constexpr Format kByValue[] = {Format::kObj,    Format::kObjWithMtl, Format::kPly,
                                        Format::kOff,    Format::kStl,        Format::kVs3,
                                        Format::kBuiltin};
  return kByValue[selector % 7];
}

/// The file extension of the formats that are one file as they are.
const char* extensionOf(Format format) {
  switch (format) {
    case Format::kObj:
      return "obj";
    case Format::kPly:
      return "ply";
    case Format::kOff:
      return "off";
    case Format::kStl:
      return "stl";
    default:
      return "vs3";
  }
}

/// A private folder for this process, made once and removed at exit. Held by a pointer that is
/// never freed, so that it outlives the atexit handler (a static would be destroyed before it).
const fs::path& scratchDir() {
  static const fs::path* const dir = [] {
    // run_fuzzer.sh names a folder it removes itself (a crash skips the atexit handler below).
    const char* given = std::getenv("RADIOSITY_FUZZ_TMPDIR");
    fs::path base = given != nullptr && *given != '\0' ? given : "/dev/shm";
    std::error_code ec;
    if (!fs::is_directory(base, ec)) base = fs::temp_directory_path();
    auto* d = new fs::path(base / ("radiosity-fuzz-" + std::to_string(::getpid())));
    fs::create_directories(*d);
    return d;
  }();
  static const bool cleanupRegistered = [] {
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(*dir, ignored);
    });
    return true;
  }();
  (void)cleanupRegistered;
  return *dir;
}

void writeFile(const fs::path& path, std::string_view content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  if (!out) __builtin_trap();  // the harness itself failed, not the loader
}

/// Built-in specs that are valid but only slow are left out: sphere level > 4 (≥ 20·4⁵
/// triangles) and rooms with more than 2000 patches (its default is 10000), as are very long
/// specs. The parser is exercised just as well by the small ones.
bool builtinSpecTooBig(const std::string& spec) {
  if (spec.size() > 256) return true;
  // strtod accepts everything the loader's from_chars does, with the same value.
  auto anyAbove = [&](const char* key, double limit, bool& seen) {
    const std::string pattern = std::string(key) + "=";
    for (size_t at = spec.find(pattern); at != std::string::npos; at = spec.find(pattern, at + 1)) {
      seen = true;
      if (std::strtod(spec.c_str() + at + pattern.size(), nullptr) > limit) return true;
    }
    return false;
  };
  bool seenLevel = false, seenPatches = false;
  if (anyAbove("level", 4, seenLevel) || anyAbove("patches", 2000, seenPatches)) return true;
  return spec.starts_with("builtin:rooms") && !seenPatches;
}

/// What every successfully loaded scene must satisfy; a violation is a bug in the loader.
void checkInvariants(const radiosity::Mesh& mesh) {
  const size_t nt = mesh.triangles.size();
  if (nt == 0) __builtin_trap();
  if (mesh.sourceFace.size() != nt || mesh.reflectance.size() != nt || mesh.emission.size() != nt)
    __builtin_trap();
  const auto nv = static_cast<int64_t>(mesh.vertices.size());
  for (const radiosity::Vec3& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(v[k])) __builtin_trap();
    }
  }
  for (size_t t = 0; t < nt; ++t) {
    for (int64_t i : mesh.triangles[t]) {
      if (i < 0 || i >= nv) __builtin_trap();
    }
    if (mesh.sourceFace[t] < 0) __builtin_trap();
    for (int c = 0; c < 3; ++c) {
      const double rho = mesh.reflectance[t][c];
      const double e = mesh.emission[t][c];
      if (!(rho >= 0 && rho <= 1)) __builtin_trap();
      if (!(e >= 0) || !std::isfinite(e)) __builtin_trap();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const Format format = formatOf(data[0]);
  const std::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);
  const fs::path& dir = scratchDir();

  // Start from an empty folder: an mtllib naming a file of an earlier input must not see it.
  std::error_code ec;
  for (const char* name :
       {"scene.obj", "scene.mtl", "scene.ply", "scene.off", "scene.stl", "scene.vs3"}) {
    fs::remove(dir / name, ec);
  }

  std::string spec;
  switch (format) {
    case Format::kObjWithMtl: {
      static constexpr std::string_view kSeparator = "\n#MTL\n";
      const size_t split = body.find(kSeparator);
      const std::string_view obj = body.substr(0, split);
      const std::string_view mtl = split == std::string_view::npos
                                       ? std::string_view()
                                       : body.substr(split + kSeparator.size());
      spec = (dir / "scene.obj").string();
      writeFile(spec, "mtllib scene.mtl\n" + std::string(obj));
      writeFile(dir / "scene.mtl", mtl);
      break;
    }
    case Format::kObj:
    case Format::kPly:
    case Format::kOff:
    case Format::kStl:
    case Format::kVs3:
      spec = (dir / (std::string("scene.") + extensionOf(format))).string();
      writeFile(spec, body);
      break;
    case Format::kBuiltin:
      spec = "builtin:" + std::string(body);
      if (builtinSpecTooBig(spec)) return 0;
      break;
  }

  try {
    const radiosity::Mesh mesh = radiosity::loadScene(spec);
    checkInvariants(mesh);
  } catch (const radiosity::Error&) {
    // Bad input, reported as it should be.
  }
  return 0;
}
