// SceneBuilder: the polygons of a built-in scene welded into one Mesh, each turned towards its lit
// side and triangulated in its plane.
#include "io/scene/scene_builder.h"

#include <algorithm>
#include <utility>

#include "io/scene/scene_internal.h"

namespace radiosity::detail {

void SceneBuilder::addPolygon(std::vector<Vec3> corners, Vec3 litSide, const Rgb& rho,
                              const Rgb& e) {
  Vec3 normal;  // Newell: robust for the slightly non-planar published Cornell quads
  for (size_t i = 0; i < corners.size(); ++i) {
    normal = normal + cross(corners[i], corners[(i + 1) % corners.size()]);
  }
  if (dot(normal, litSide) < 0) std::reverse(corners.begin(), corners.end());
  std::vector<int64_t> ids;
  for (const Vec3& p : corners) ids.push_back(vertexId(p));
  const PolygonTriangulation split = triangulatePolygon(corners);
  for (const Vec3& p : split.added) ids.push_back(vertexId(p));
  for (const auto& t : split.triangles) {
    mesh_.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
    mesh_.sourceFace.push_back(faces_);
    mesh_.reflectance.push_back(rho);
    mesh_.emission.push_back(e);
    mesh_.label.push_back(label_);
  }
  ++faces_;
}

void SceneBuilder::setLabel(const std::string& name) {
  const auto it = std::find(mesh_.labelNames.begin(), mesh_.labelNames.end(), name);
  label_ = static_cast<int32_t>(it - mesh_.labelNames.begin());
  if (it == mesh_.labelNames.end()) mesh_.labelNames.push_back(name);
}

Mesh SceneBuilder::take() {
  if (mesh_.labelNames.empty()) {
    mesh_.label.clear();
  } else if (std::find(mesh_.label.begin(), mesh_.label.end(), -1) != mesh_.label.end()) {
    setLabel("unnamed");
    std::replace(mesh_.label.begin(), mesh_.label.end(), -1, label_);
  }
  return std::move(mesh_);
}

int64_t SceneBuilder::vertexId(Vec3 p) {
  const auto [it, added] = ids_.emplace(std::array<double, 3>{p.x, p.y, p.z}, ids_.size());
  if (added) mesh_.vertices.push_back(p);
  return it->second;
}

Vec3 centroid(const std::vector<Vec3>& points) {
  Vec3 sum;
  for (const Vec3& p : points) sum = sum + p;
  return (1.0 / static_cast<double>(points.size())) * sum;
}

}  // namespace radiosity::detail
