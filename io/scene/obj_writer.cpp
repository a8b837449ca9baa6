// writeSceneObj(): OBJ + MTL that loadScene() reads back to the same mesh, bit for bit.
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"

namespace radiosity {
namespace {

/// A text file opened for writing under `name`; close() reports any failed write for `shown`.
class CheckedFile {
 public:
  CheckedFile(const std::string& name, std::string shown) : shown_(std::move(shown)) {
    file_ = std::fopen(name.c_str(), "wbx");  // x: never an existing file
    if (file_ == nullptr) fail();
  }
  ~CheckedFile() {
    if (file_ != nullptr) std::fclose(file_);
  }
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  FILE* get() const { return file_; }
  /// Flushes and closes; throws if any write failed.
  void close() {
    const bool bad = std::ferror(file_) != 0;
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (bad || rc != 0) fail();
  }

 private:
  [[noreturn]] void fail() const {
    throw Error(exit_code::kFailure, "cannot write '" + shown_ + "': " + std::strerror(errno));
  }

  std::string shown_;
  FILE* file_ = nullptr;
};

}  // namespace

void writeSceneObj(const Mesh& mesh, const std::string& objPath) {
  const std::filesystem::path mtlPath = std::filesystem::path(objPath).replace_extension(".mtl");
  if (mtlPath == std::filesystem::path(objPath)) {
    throw Error(exit_code::kFailure, "cannot write '" + objPath + "': the name ends in .mtl");
  }

  // One material per distinct (ρ, E), numbered in order of first use.
  std::map<std::pair<Rgb, Rgb>, int> materialId;
  std::vector<const std::pair<Rgb, Rgb>*> materials;
  std::vector<int> materialOf(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [it, added] = materialId.emplace(std::pair{mesh.reflectance[t], mesh.emission[t]},
                                                static_cast<int>(materials.size()));
    if (added) materials.push_back(&it->first);
    materialOf[t] = it->second;
  }

  // %.17g round-trips every double exactly.
  OutputBatch batch;
  CheckedFile mtl(batch.stage(mtlPath.string()), mtlPath.string());
  for (size_t m = 0; m < materials.size(); ++m) {
    const Rgb& kd = materials[m]->first;
    const Rgb& ke = materials[m]->second;
    std::fprintf(mtl.get(), "newmtl m%zu\nKd %.17g %.17g %.17g\nKe %.17g %.17g %.17g\n\n", m, kd[0],
                 kd[1], kd[2], ke[0], ke[1], ke[2]);
  }
  mtl.close();

  CheckedFile obj(batch.stage(objPath), objPath);
  std::fprintf(obj.get(), "# %zu vertices, %zu triangles; Kd = reflectance, Ke = emission\n",
               mesh.vertices.size(), mesh.triangles.size());
  // A name that starts with white space would lose it to the reader's tokens (`scene -o
  // ' lead.obj'` wrote an OBJ it could not read back): "./" keeps it, and the reader takes the
  // whole rest of the line where such a file exists.
  std::string mtlName = mtlPath.filename().string();
  if (!mtlName.empty() && std::isspace(static_cast<unsigned char>(mtlName[0])))
    mtlName = "./" + mtlName;
  std::fprintf(obj.get(), "mtllib %s\n", mtlName.c_str());
  for (const Vec3& v : mesh.vertices)
    std::fprintf(obj.get(), "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
  int current = -1;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (materialOf[t] != current) {
      current = materialOf[t];
      std::fprintf(obj.get(), "usemtl m%d\n", current);
    }
    const Triangle& tri = mesh.triangles[t];
    std::fprintf(obj.get(), "f %lld %lld %lld\n", static_cast<long long>(tri[0] + 1),
                 static_cast<long long>(tri[1] + 1), static_cast<long long>(tri[2] + 1));
  }
  obj.close();

  // Staged MTL first: an OBJ must never appear without its materials.
  batch.commit();
}

}  // namespace radiosity
