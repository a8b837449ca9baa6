#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::render {

namespace {

constexpr double kFitMargin = 1.05;  // leave a little black around the scene

// The three unit axes of a camera looking along `forward` with `upHint` up.
void makeBasis(Vec3 forward, Vec3 upHint, PinholeCamera& camera) {
  // The hint scaled by its largest component first: at 1e±300 its cross product with the view
  // under- or overflowed, and such an --up was called parallel.
  const double largest = std::max({std::abs(upHint.x), std::abs(upHint.y), std::abs(upHint.z)});
  if (largest > 0 && std::isfinite(largest))
    for (int k = 0; k < 3; ++k) upHint[k] = std::ldexp(upHint[k], -std::ilogb(largest));
  Vec3 right = cross(forward, upHint);
  if (!(length(right) > 1e-9 * length(upHint)))
    throw Error(exit_code::kUsage, "render: the camera's up vector is parallel to its view");
  camera.forward = forward;
  camera.right = normalize(right);
  camera.up = cross(camera.right, forward);
}

}  // namespace

PinholeCamera makeCamera(const Camera& options, Vec3 lo, Vec3 hi, double aspect) {
  if (!(options.fovDegrees > 0 && options.fovDegrees < 180))
    throw Error(exit_code::kUsage, "render: the field of view must be in (0, 180) degrees");
  PinholeCamera camera;
  camera.aspect = aspect;
  camera.tanHalfFov = std::tan(options.fovDegrees * std::numbers::pi / 360);
  Vec3 lookAt = options.lookAt.value_or(0.5 * (lo + hi));

  if (options.eye) {
    Vec3 toTarget = lookAt - *options.eye;
    if (!(length(toTarget) > 0))
      throw Error(exit_code::kUsage, "render: the camera's eye and lookAt are the same point");
    camera.eye = *options.eye;
    makeBasis(normalize(toTarget), options.up, camera);
    return camera;
  }

  // Back away from lookAt along −z until every corner of the box projects inside the image:
  // a corner at (x, y, z) in camera axes (z ahead of lookAt) needs |y| ≤ tan·(d + z) and
  // |x| ≤ tan·aspect·(d + z).
  makeBasis({0, 0, 1}, options.up, camera);
  double distance = 0;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
    Vec3 q = p - lookAt;
    double x = std::abs(dot(q, camera.right)), y = std::abs(dot(q, camera.up));
    double z = dot(q, camera.forward);
    distance = std::max(distance, kFitMargin * y / camera.tanHalfFov - z);
    distance = std::max(distance, kFitMargin * x / (camera.tanHalfFov * aspect) - z);
  }
  // A flat scene seen edge-on would put the eye on lookAt: keep a sensible distance.
  distance = std::max(distance, 1e-3 * length(hi - lo));
  if (!(distance > 0)) distance = 1;
  camera.eye = lookAt - distance * camera.forward;
  return camera;
}

}  // namespace radiosity::render
