// The Embree adapter: one device and one BVH over the patches, built once per rank.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

namespace {

// Embree reports device errors through this callback; turn the next one into an exception.
void onEmbreeError(void* userPtr, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(userPtr);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
          (message ? message : "(no message)");
}

}  // namespace

struct SceneTracer::Embree {
  RTCDevice device = nullptr;  ///< owned
  RTCScene scene = nullptr;    ///< owned
  std::string lastError;

  void check(const char* what) {
    if (!lastError.empty()) throw Error(exit_code::kFailure, std::string(what) + ": " + lastError);
  }
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

SceneTracer::SceneTracer(const Mesh& mesh, int threads) : embree_(std::make_unique<Embree>()) {
  Embree& e = *embree_;
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  e.device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!e.device) throw Error(exit_code::kFailure, "cannot create an Embree device");
  rtcSetDeviceErrorFunction(e.device, onEmbreeError, &e.lastError);

  // Embree takes float vertices; the geometry stays in double everywhere else.
  RTCGeometry geometry = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  e.check("allocating the Embree geometry");
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    for (int k = 0; k < 3; ++k) vertices[3 * v + k] = static_cast<float>(mesh.vertices[v][k]);
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  }
  rtcCommitGeometry(geometry);
  e.scene = rtcNewScene(e.device);
  // Robust mode: watertight edges, so rays cannot slip between patches of a closed scene.
  rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(e.scene, RTC_BUILD_QUALITY_HIGH);
  rtcAttachGeometry(e.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(e.scene);
  e.check("building the Embree BVH");

  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  sceneSize_ = length(hi - lo);
}

SceneTracer::~SceneTracer() = default;

std::optional<SceneTracer::Hit> SceneTracer::intersect(Vec3 origin, Vec3 direction, double tNear,
                                                       double tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayHit{};
  rayHit.ray.org_x = static_cast<float>(origin.x);
  rayHit.ray.org_y = static_cast<float>(origin.y);
  rayHit.ray.org_z = static_cast<float>(origin.z);
  rayHit.ray.dir_x = static_cast<float>(direction.x);
  rayHit.ray.dir_y = static_cast<float>(direction.y);
  rayHit.ray.dir_z = static_cast<float>(direction.z);
  rayHit.ray.tnear = static_cast<float>(tNear);
  rayHit.ray.tfar = tFar > std::numeric_limits<float>::max()
                        ? std::numeric_limits<float>::infinity()
                        : static_cast<float>(tFar);
  rayHit.ray.mask = 0xFFFFFFFFu;
  rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(embree_->scene, &context, &rayHit);
  if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  // Embree's Ng has the orientation of Mesh::normal (tests/formfactor_test.cpp checks it).
  return Hit{static_cast<int64_t>(rayHit.hit.primID),
             rayHit.ray.tfar,
             rayHit.hit.u,
             rayHit.hit.v,
             {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z}};
}

void SceneTracer::RayBatch::resize(size_t n) {
  for (auto* v : {&originX, &originY, &originZ, &directionX, &directionY, &directionZ, &tFar}) {
    v->resize(n);
  }
}

void SceneTracer::intersect(const RayBatch& rays, HitBatch& hits) const {
  const size_t n = rays.size();
  for (auto* v : {&hits.tNear, &hits.time, &hits.normalX, &hits.normalY, &hits.normalZ, &hits.u,
                  &hits.v, &hits.distance}) {
    v->resize(n);
  }
  for (auto* v :
       {&hits.mask, &hits.id, &hits.flags, &hits.primitive, &hits.geometry, &hits.instance}) {
    v->resize(n);
  }
  hits.patch.resize(n);
  hits.front.resize(n);
  std::fill(hits.tNear.begin(), hits.tNear.end(), 0.0f);
  std::fill(hits.mask.begin(), hits.mask.end(), 0xFFFFFFFFu);
  std::fill(hits.geometry.begin(), hits.geometry.end(), RTC_INVALID_GEOMETRY_ID);
  std::copy(rays.tFar.begin(), rays.tFar.end(), hits.distance.begin());  // tfar is in and out

  // One stream call for the batch: Embree regroups the rays into packets where that pays.
  RTCRayHitNp stream{};
  stream.ray = {const_cast<float*>(rays.originX.data()),
                const_cast<float*>(rays.originY.data()),
                const_cast<float*>(rays.originZ.data()),
                hits.tNear.data(),
                const_cast<float*>(rays.directionX.data()),
                const_cast<float*>(rays.directionY.data()),
                const_cast<float*>(rays.directionZ.data()),
                hits.time.data(),
                hits.distance.data(),
                hits.mask.data(),
                hits.id.data(),
                hits.flags.data()};
  stream.hit.Ng_x = hits.normalX.data();
  stream.hit.Ng_y = hits.normalY.data();
  stream.hit.Ng_z = hits.normalZ.data();
  stream.hit.u = hits.u.data();
  stream.hit.v = hits.v.data();
  stream.hit.primID = hits.primitive.data();
  stream.hit.geomID = hits.geometry.data();
  stream.hit.instID[0] = hits.instance.data();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersectNp(embree_->scene, &context, &stream, static_cast<unsigned>(n));

  for (size_t k = 0; k < n; ++k) {
    const bool hit = hits.geometry[k] != RTC_INVALID_GEOMETRY_ID;
    hits.patch[k] = hit ? static_cast<int64_t>(hits.primitive[k]) : -1;
    // Embree's Ng has the orientation of Mesh::normal.
    hits.front[k] = hit && rays.directionX[k] * hits.normalX[k] +
                                   rays.directionY[k] * hits.normalY[k] +
                                   rays.directionZ[k] * hits.normalZ[k] <
                               0.0f;
  }
}

}  // namespace radiosity::formfactor
