// Private to io/scene/: what the readers through OpenMesh (PLY and OFF in openmesh_reader.cpp,
// STL in stl_reader.cpp) share: the mesh type they read into and the capture of OpenMesh's
// messages. OpenMesh's types stay in io/scene/.
#pragma once

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity::detail {

struct SceneTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;  // keep double coordinates where the file has them
  using Color = OpenMesh::Vec3f;  // OpenMesh scales byte colours to [0, 1] for float colours
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<SceneTraits>;

/// Routes OpenMesh's diagnostics (omerr/omlog, and a few direct writes to std::cerr) into a
/// string while alive, so that library code prints nothing and the caller sees them as warnings.
/// omerr and omlog write to std::cerr and std::clog, so redirecting those two catches all; their
/// connect()/disconnect() are not used because disconnect() leaks the target (OpenMesh 9.0).
class CaptureOpenMeshMessages {
 public:
  CaptureOpenMeshMessages() {
    ::omerr().flush();
    ::omlog().flush();
    oldCerr_ = std::cerr.rdbuf(text_.rdbuf());
    oldClog_ = std::clog.rdbuf(text_.rdbuf());
  }
  ~CaptureOpenMeshMessages() {
    ::omerr().flush();
    ::omlog().flush();
    std::cerr.rdbuf(oldCerr_);
    std::clog.rdbuf(oldClog_);
  }
  CaptureOpenMeshMessages(const CaptureOpenMeshMessages&) = delete;
  CaptureOpenMeshMessages& operator=(const CaptureOpenMeshMessages&) = delete;

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
  std::streambuf* oldClog_ = nullptr;
};

/// "; message" for each of OpenMesh's messages, to end an error with.
inline std::string joined(const std::vector<std::string>& messages) {
  std::string detail;
  for (const auto& m : messages) detail.append("; ").append(m);
  return detail;
}

}  // namespace radiosity::detail
