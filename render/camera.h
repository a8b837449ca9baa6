// The pinhole camera of render/: options + scene bounds → a ray per image point. Private to
// render/ (and its tests).
#pragma once

#include "core/vec3.h"
#include "render/render.h"

namespace radiosity::render {

struct PinholeCamera {
  Vec3 eye;
  Vec3 forward, right, up;  ///< orthonormal; right = forward × up
  double tanHalfFov = 0;    ///< vertical
  double aspect = 1;        ///< width / height

  /// Unit direction through the image point (x, y) in pixels, (0, 0) the top-left corner.
  Vec3 direction(double x, double y, int width, int height) const {
    double sx = (2 * x / width - 1) * tanHalfFov * aspect;
    double sy = (1 - 2 * y / height) * tanHalfFov;
    return normalize(forward + sx * right + sy * up);
  }
};

/// Fills in the defaults of `camera` (see Camera) for a scene with bounds [lo, hi] and an
/// image of the given aspect. Throws Error(kUsage) for a camera that cannot be built
/// (eye = lookAt, up parallel to the view, field of view outside (0°, 180°)).
PinholeCamera makeCamera(const Camera& camera, Vec3 lo, Vec3 hi, double aspect);

}  // namespace radiosity::render
