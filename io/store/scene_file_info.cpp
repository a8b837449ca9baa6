// `radiosity info` for an HDF5 scene file: recognising one, and what it holds. The scene is read
// and checked whole (so info also says whether solve would take it), on the calling rank alone.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/scene_file.h"
#include "io/store/scene_file_format.h"

namespace radiosity {
namespace {

namespace format = scene_format;

/// Materials listed one a line; beyond this many, only counted.
constexpr size_t kListedMaterials = 24;

std::string triple(const Rgb& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.6g %.6g %.6g", v[0], v[1], v[2]);
  return text;
}

std::string point(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v.x, v.y, v.z);
  return text;
}

/// The optional text attribute `name` of the root, "" if absent or not text.
std::string textAttribute(hid_t file, const std::string& path, const char* name) {
  if (h5::check(H5Aexists(file, name), "H5Aexists") <= 0) return "";
  try {
    return h5::readAttribute<std::string>(file, path, name);
  } catch (const InputError&) {
    return "";
  }
}

}  // namespace

bool isSceneFile(const std::string& path) { return h5::fileKind(path) == format::kKind; }

std::string describeSceneFile(const std::string& path) {
  const Mesh mesh = readSceneFile(MPI_COMM_SELF, path);
  std::string source;
  std::vector<std::pair<std::string, std::string>> software;
  {
    h5::QuietErrors quiet;
    h5::Handle file = h5::openFile(path, "scene file");
    try {
      source = textAttribute(file.get(), path, format::attribute::kSource);
      const std::string_view prefix = format::attribute::kSoftwarePrefix;
      for (const std::string& name : h5::attributeNames(file.get()))
        if (name.starts_with(prefix))
          software.emplace_back(name.substr(prefix.size()),
                                textAttribute(file.get(), path, name.c_str()));
    } catch (const h5::Failure& e) {
      h5::fail(path, e.what());
    }
  }
  // The materials as the file numbers them: distinct (ρ, E, label) in order of first use.
  struct Material {
    Rgb rho, e;
    int32_t label;
    int64_t triangles;
  };
  std::vector<Material> materials;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const int32_t label = mesh.hasLabels() ? mesh.label[t] : -1;
    bool found = false;
    for (Material& m : materials) {
      if (m.rho == mesh.reflectance[t] && m.e == mesh.emission[t] && m.label == label) {
        ++m.triangles;
        found = true;
        break;
      }
    }
    if (!found) materials.push_back({mesh.reflectance[t], mesh.emission[t], label, 1});
    if (materials.size() > kListedMaterials) break;  // only counted from here on
  }
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);

  std::ostringstream out;
  out << "file: " << path << "\n"
      << "scene file (format " << format::kFormatVersion << ")"
      << (source.empty() ? "" : ", made from " + source) << "\n"
      << "  triangles: " << mesh.triangleCount() << "\n"
      << "  vertices: " << mesh.vertices.size() << "\n"
      << "  length unit: "
      << (mesh.lengthUnit.empty() ? std::string("not stated") : mesh.lengthUnit) << "\n"
      << "  bounding box: " << point(lo) << " to " << point(hi) << "\n"
      << "  total area: " << mesh.totalArea() << "\n"
      << "  labels: " << (mesh.hasLabels() ? std::to_string(mesh.labelNames.size()) : "none")
      << "\n";
  if (materials.size() <= kListedMaterials) {
    out << "  materials: " << materials.size() << " (rho red green blue | E red green blue"
        << (mesh.hasLabels() ? " | label" : "") << " | triangles)\n";
    for (size_t m = 0; m < materials.size(); ++m) {
      out << "    " << m << ": " << triple(materials[m].rho) << " | " << triple(materials[m].e);
      if (materials[m].label >= 0) out << " | " << mesh.labelNames[materials[m].label];
      out << " | " << materials[m].triangles << "\n";
    }
  } else {
    out << "  materials: more than " << kListedMaterials << "\n";
  }
  if (!software.empty()) {
    out << "  made by:";
    for (const auto& [name, version] : software) out << " " << name << " " << version << ";";
    out << "\n";
  }
  for (const std::string& warning : mesh.warnings) out << "  warning: " << warning << "\n";
  return out.str();
}

}  // namespace radiosity
