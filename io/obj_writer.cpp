// writeSceneObj(): OBJ + MTL that loadScene() reads back to the same mesh, bit for bit.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "io/atomic_file.h"
#include "io/io.h"

namespace radiosity {
namespace {

/// A file written under a temporary name in its final folder, renamed into place by commit();
/// removed if never committed, so a failed write leaves nothing behind.
class TempFile {
 public:
  explicit TempFile(std::string path)
      : path_(std::move(path)), temp_(temporaryNameFor(path_)) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (file_ == nullptr) fail();
  }
  ~TempFile() {
    if (file_ != nullptr) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  FILE* get() const { return file_; }
  /// Flushes and closes; throws if any write failed.
  void close() {
    const bool bad = std::ferror(file_) != 0;
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (bad || rc != 0) fail();
  }
  void commit() {
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail();
    committed_ = true;
    removeStaleTemporaries(path_);
  }

 private:
  [[noreturn]] void fail() const {
    throw Error(exit_code::kFailure, "cannot write '" + path_ + "': " + std::strerror(errno));
  }

  std::string path_, temp_;
  FILE* file_ = nullptr;
  bool committed_ = false;
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
  TempFile mtl(mtlPath.string());
  for (size_t m = 0; m < materials.size(); ++m) {
    const Rgb& kd = materials[m]->first;
    const Rgb& ke = materials[m]->second;
    std::fprintf(mtl.get(), "newmtl m%zu\nKd %.17g %.17g %.17g\nKe %.17g %.17g %.17g\n\n", m, kd[0],
                 kd[1], kd[2], ke[0], ke[1], ke[2]);
  }
  mtl.close();

  TempFile obj(objPath);
  std::fprintf(obj.get(), "# %zu vertices, %zu triangles; Kd = reflectance, Ke = emission\n",
               mesh.vertices.size(), mesh.triangles.size());
  std::fprintf(obj.get(), "mtllib %s\n", mtlPath.filename().string().c_str());
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

  // The MTL first: an OBJ must never appear without its materials.
  mtl.commit();
  obj.commit();
}

}  // namespace radiosity
