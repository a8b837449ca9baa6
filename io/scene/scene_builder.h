// Private to io/scene: what the built-in scenes are built with: their parameters, SceneBuilder
// (polygons welded into one Mesh, each turned towards its lit side), centroid() and grey().
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::detail {

/// A built-in scene's parameters by name ("builtin:NAME?key=value&..."), defaults filled in.
using Params = std::map<std::string, double>;

/// Collects polygons into a Mesh: welds vertices with equal coordinates (so neighbours share
/// indices) and turns each polygon so that its right-hand-rule normal points along `litSide`.
class SceneBuilder {
 public:
  void addPolygon(std::vector<Vec3> corners, Vec3 litSide, const Rgb& rho, const Rgb& e);
  /// Labels the polygons added from now on (for messages such as the winding warning).
  void setLabel(const std::string& name);
  void addTriangle(Vec3 a, Vec3 b, Vec3 c, Vec3 litSide, const Rgb& rho, const Rgb& e) {
    addPolygon({a, b, c}, litSide, rho, e);
  }
  /// The mesh; without labels if setLabel() was never called, else polygons added before the
  /// first setLabel() are labelled 'unnamed'.
  Mesh take();

 private:
  int64_t vertexId(Vec3 p);

  Mesh mesh_;
  std::map<std::array<double, 3>, int64_t> ids_;
  int64_t faces_ = 0;
  int32_t label_ = -1;  ///< -1: no label set yet
};

/// The mean of `points`.
Vec3 centroid(const std::vector<Vec3>& points);

inline Rgb grey(double v) { return {v, v, v}; }

}  // namespace radiosity::detail
