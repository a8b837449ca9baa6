// PLY and OFF through OpenMesh. Its types stay in this file.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <fstream>
#include <iostream>
#include <sstream>

#include "io/scene_internal.h"

namespace radiosity::detail {
namespace {

struct SceneTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;  // keep double coordinates where the file has them
  using Color = OpenMesh::Vec3f;  // OpenMesh scales byte colours to [0, 1] for float colours
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<SceneTraits>;

/// Routes OpenMesh's diagnostics (omerr/omlog, and a few direct writes to std::cerr) into a
/// string while alive, so that library code prints nothing and the caller sees them as warnings.
class CaptureOpenMeshMessages {
 public:
  CaptureOpenMeshMessages() {
    oldCerr_ = std::cerr.rdbuf(text_.rdbuf());
    hadCerr_ = ::omerr().disconnect(std::cerr);
    hadClog_ = ::omlog().disconnect(std::clog);
    ::omerr().connect(text_);
    ::omlog().connect(text_);
  }
  ~CaptureOpenMeshMessages() {
    ::omerr().flush();
    ::omlog().flush();
    ::omerr().disconnect(text_);
    ::omlog().disconnect(text_);
    if (hadCerr_) ::omerr().connect(std::cerr);
    if (hadClog_) ::omlog().connect(std::clog);
    std::cerr.rdbuf(oldCerr_);
  }
  std::vector<std::string> lines() {
    ::omerr().flush();
    ::omlog().flush();
    std::vector<std::string> out;
    std::istringstream in(text_.str());
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) out.push_back(line);
    }
    return out;
  }

 private:
  std::ostringstream text_;
  std::streambuf* oldCerr_ = nullptr;
  bool hadCerr_ = false;
  bool hadClog_ = false;
};

}  // namespace

Mesh readOpenMeshFile(const std::string& path) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw InputError(path + ": cannot read file");
  }
  PolyMesh polyMesh;
  polyMesh.request_face_colors();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceColor;
  std::vector<std::string> messages;
  {
    CaptureOpenMeshMessages capture;
    const bool ok = OpenMesh::IO::read_mesh(polyMesh, path, options);
    messages = capture.lines();
    if (!ok) {
      std::string detail;
      for (const auto& m : messages) detail += "; " + m;
      throw InputError(path + ": not a readable mesh file (OpenMesh reader failed" + detail + ")");
    }
  }
  Mesh mesh;
  for (const auto& m : messages) {
    // OpenMesh skips faces with bad indices instead of failing; for us that is bad input.
    if (m.find("invalid vertex index") != std::string::npos) {
      throw InputError(path + ": face refers to a vertex that does not exist (" + m + ")" +
                       (path.ends_with(".off") || path.ends_with(".OFF")
                            ? "; note: face colours in OFF need a COFF header"
                            : ""));
    }
    mesh.warnings.push_back(path + ": OpenMesh: " + m);
  }

  mesh.vertices.reserve(polyMesh.n_vertices());
  for (const auto vh : polyMesh.vertices()) {
    const auto& p = polyMesh.point(vh);
    mesh.vertices.push_back({p[0], p[1], p[2]});
  }
  const bool hasColour = options.face_has_color();
  if (!hasColour) {
    mesh.warnings.push_back(path + ": no face colours; every face gets ρ = 0.5, E = 0");
  }
  for (const auto fh : polyMesh.faces()) {
    std::vector<int64_t> corners;
    for (const auto vh : polyMesh.fv_range(fh)) corners.push_back(vh.idx());
    Rgb rho = kDefaultReflectance;
    if (hasColour) {
      const auto& c = polyMesh.color(fh);
      rho = {c[0], c[1], c[2]};
    }
    std::vector<Vec3> polygon;
    for (int64_t i : corners) polygon.push_back(mesh.vertices[i]);
    // Same as the OBJ reader: the fan for convex polygons, correct for concave ones.
    for (const auto& t : triangulatePolygon(polygon)) {
      mesh.triangles.push_back({corners[t[0]], corners[t[1]], corners[t[2]]});
      mesh.sourceFace.push_back(fh.idx());
      mesh.reflectance.push_back(rho);
      mesh.emission.push_back({0, 0, 0});
    }
  }
  return mesh;
}

}  // namespace radiosity::detail
