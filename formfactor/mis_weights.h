// Private to formfactor/: what the rows' samples and the clusters' pilots share to weigh an
// emitter sample against a hemisphere sample (multiple importance sampling, balance heuristic):
// the two densities of a direction, the emitters' brightness, and the points of a ray batch.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <vector>

#include "formfactor/formfactor.h"
#include "formfactor/light_choice.h"

namespace radiosity::formfactor {

// Shadow rays stop this share of the distance short of the sampled point, so that they test
// what lies between; asking for a hit on the point's own patch instead loses the points that a
// grazing ray, in float, finds first on a neighbouring patch.
inline constexpr double kShadowGap = 1e-4;

inline bool isEmitter(const Mesh& patches, int64_t j) {
  const Rgb& e = patches.emission[j];
  return e[0] > 0 || e[1] > 0 || e[2] > 0;
}

inline double meanEmission(const Mesh& patches, int64_t j) {
  const Rgb& e = patches.emission[j];
  return (e[0] + e[1] + e[2]) / 3;
}

// The two densities of a direction in solid angle: cosine-weighted hemisphere about the
// patch's normal, and the light choice's point on emitter j (normal normals[j]) seen at
// distance r.
inline double hemisphereDensity(Vec3 direction, Vec3 normal) {
  return std::max(0.0, dot(direction, normal)) / std::numbers::pi;
}
inline double emitterDensity(const LightChoice& lights, const std::vector<Vec3>& normals,
                             Vec3 direction, int64_t j, double r) {
  const double cosine = -dot(direction, normals[j]);
  return cosine > 0 ? r * r * lights.densityPerArea(j) / cosine : 0.0;
}

inline Vec3 batchOrigin(const SceneTracer::RayBatch& rays, size_t k) {
  return {rays.originX[k], rays.originY[k], rays.originZ[k]};
}
inline Vec3 batchDirection(const SceneTracer::RayBatch& rays, size_t k) {
  return {rays.directionX[k], rays.directionY[k], rays.directionZ[k]};
}

}  // namespace radiosity::formfactor
