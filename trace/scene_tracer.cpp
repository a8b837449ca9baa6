// The Embree adapter: one device and one BVH over the patches, built once per rank.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "trace/trace.h"
#include "trace/twins.h"

namespace radiosity::trace {

std::string embreeVersion() { return RTC_VERSION_STRING; }

namespace {

// Embree reports device errors through this callback; turn the next one into an exception.
void onEmbreeError(void* userPtr, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(userPtr);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
          (message ? message : "(no message)");
}

// cos 30°: a front face found near a back-face hit is the back face's coincident other side
// only when their normals are this near opposite.
constexpr float kOtherSideCosine = 0.8660254f;

// The context of a search for the front face coincident with a back face a ray met: Embree
// hands the filter the context it was given, so the back face's normal rides behind it.
struct OtherSideContext {
  RTCIntersectContext context;  // first: Embree's pointer to it is a pointer to this
  float backNormal[3];
};

// Drops every candidate hit on the back of a face (the direction along the geometric normal,
// which points to the lit side), and every front that does not face the back face's other side
// (within 30°): a ray over a room's corner from outside meets one wall's back and, within the
// search window, the other wall's front, which is not the light's way in.
void keepOtherSides(const RTCFilterFunctionNArguments* args) {
  const float* back = reinterpret_cast<const OtherSideContext*>(args->context)->backNormal;
  for (unsigned i = 0; i < args->N; ++i) {
    const float nx = RTCHitN_Ng_x(args->hit, args->N, i), ny = RTCHitN_Ng_y(args->hit, args->N, i),
                nz = RTCHitN_Ng_z(args->hit, args->N, i);
    const float facing = RTCRayN_dir_x(args->ray, args->N, i) * nx +
                         RTCRayN_dir_y(args->ray, args->N, i) * ny +
                         RTCRayN_dir_z(args->ray, args->N, i) * nz;
    const float opposite = nx * back[0] + ny * back[1] + nz * back[2];
    const float lengths = std::sqrt((nx * nx + ny * ny + nz * nz) *
                                    (back[0] * back[0] + back[1] * back[1] + back[2] * back[2]));
    if (!(facing < 0.0f) || !(opposite < -kOtherSideCosine * lengths)) args->valid[i] = 0;
  }
}

// The stream's hits as patch ids and sides; returns the number of back-face hits.
size_t readHits(const SceneTracer::RayBatch& rays, SceneTracer::HitBatch& hits) {
  size_t backHits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {  // a plain loop: the compiler vectorises it
    const bool hit = hits.geometry[k] != RTC_INVALID_GEOMETRY_ID;
    hits.patch[k] = hit ? static_cast<int64_t>(hits.primitive[k]) : -1;
    hits.front[k] = hit && rays.directionX[k] * hits.normalX[k] +
                                   rays.directionY[k] * hits.normalY[k] +
                                   rays.directionZ[k] * hits.normalZ[k] <
                               0.0f;
    backHits += hit && !hits.front[k];
  }
  return backHits;
}

// The same where some triangles have twins: a hit on the back of one becomes a hit on the
// front of its twin. Returns the number of back-face hits left.
size_t readHitsWithTwins(const SceneTracer::RayBatch& rays, SceneTracer::HitBatch& hits,
                         const std::vector<int64_t>& twin,
                         const std::vector<uint8_t>& twinCorners) {
  size_t backHits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    if (hits.geometry[k] == RTC_INVALID_GEOMETRY_ID) {
      hits.patch[k] = -1;
      hits.front[k] = 0;
      continue;
    }
    const int64_t t = hits.primitive[k];
    const float facing = rays.directionX[k] * hits.normalX[k] +
                         rays.directionY[k] * hits.normalY[k] +
                         rays.directionZ[k] * hits.normalZ[k];
    hits.patch[k] = t;
    hits.front[k] = facing < 0.0f;
    if (hits.front[k]) continue;
    if (twin[t] < 0) {
      ++backHits;
      continue;
    }
    twinBarycentrics(twinCorners[t], hits.u[k], hits.v[k]);
    hits.patch[k] = twin[t];
    hits.front[k] = 1;
    hits.normalX[k] = -hits.normalX[k];
    hits.normalY[k] = -hits.normalY[k];
    hits.normalZ[k] = -hits.normalZ[k];
  }
  return backHits;
}

}  // namespace

namespace {

// SceneTracer::offset() of every patch of `mesh`, whose bounding box has this centre and size.
std::vector<double> patchOffsets(const Mesh& mesh, Vec3 centre, double sceneSize) {
  std::vector<double> offsets(mesh.triangles.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    double longest = 0, farthest = 0;
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, length(mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k)));
      farthest = std::max(farthest, length(mesh.corner(t, k) - centre));
    }
    const double rounding = SceneTracer::kCoincidentFaces * farthest;
    offsets[t] = std::min(SceneTracer::kCoincidentFaces * sceneSize,
                          std::max(rounding, SceneTracer::kPatchShare * longest));
  }
  return offsets;
}

}  // namespace

struct SceneTracer::Embree {
  RTCDevice device = nullptr;  ///< owned
  RTCScene scene = nullptr;    ///< owned
  std::string lastError;

  /// The nearest front face that `ray` meets within `window` of `tBack` (where it met the back
  /// of a face of geometric normal `backNormal`) and within its own [tnear, tfar], if any, that
  /// faces that back (keepOtherSides). The window is clipped to the ray's segment so that the
  /// hit still lies where the caller asked.
  std::optional<RTCRayHit> frontFaceNear(const RTCRay& ray, float tBack, float window,
                                         const float (&backNormal)[3]) const {
    RTCRayHit again{};
    again.ray = ray;
    again.ray.tnear = std::max(ray.tnear, tBack - window);
    again.ray.tfar = std::min(ray.tfar, tBack + window);
    again.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    OtherSideContext search;
    rtcInitIntersectContext(&search.context);
    search.context.filter = keepOtherSides;
    std::copy(backNormal, backNormal + 3, search.backNormal);
    rtcIntersect1(scene, &search.context, &again);
    if (again.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return again;
  }

  /// Each back-face hit of the batch with a front face near it (frontFaceNear) becomes a hit
  /// on that front face. Ray by ray: back-face hits are few where the model is right, and a
  /// ray's answer then depends on the ray alone.
  void frontFacesNearBackHits(const RayBatch& rays, HitBatch& hits,
                              const std::vector<double>& window) const {
    for (size_t k = 0; k < rays.size(); ++k) {
      if (hits.patch[k] < 0 || hits.front[k]) continue;
      RTCRay ray{};
      ray.org_x = rays.originX[k];
      ray.org_y = rays.originY[k];
      ray.org_z = rays.originZ[k];
      ray.dir_x = rays.directionX[k];
      ray.dir_y = rays.directionY[k];
      ray.dir_z = rays.directionZ[k];
      ray.tnear = hits.tNear[k];
      ray.tfar = rays.tFar[k];
      ray.mask = 0xFFFFFFFFu;
      const float backNormal[3] = {hits.normalX[k], hits.normalY[k], hits.normalZ[k]};
      const auto near = frontFaceNear(ray, hits.distance[k],
                                      static_cast<float>(window[hits.patch[k]]), backNormal);
      if (!near) continue;
      hits.patch[k] = static_cast<int64_t>(near->hit.primID);
      hits.front[k] = 1;
      hits.distance[k] = near->ray.tfar;
      hits.u[k] = near->hit.u;
      hits.v[k] = near->hit.v;
      hits.normalX[k] = near->hit.Ng_x;
      hits.normalY[k] = near->hit.Ng_y;
      hits.normalZ[k] = near->hit.Ng_z;
    }
  }

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
  // Thin two-sided surfaces need the context filter (frontFaceNear); Embree builds may leave
  // filter functions out.
  if (rtcGetDeviceProperty(e.device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0) {
    throw Error(exit_code::kFailure,
                "this Embree was built without filter functions (EMBREE_FILTER_FUNCTION=OFF)");
  }

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
  // The context filter: only frontFaceNear() sets one.
  rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(e.scene, RTC_BUILD_QUALITY_HIGH);
  rtcAttachGeometry(e.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(e.scene);
  e.check("building the Embree BVH");

  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  sceneSize_ = length(hi - lo);
  offset_ = patchOffsets(mesh, 0.5 * (lo + hi), sceneSize_);

  Twins twins = findTwins(mesh);
  twin_ = std::move(twins.twin);
  twinCorners_ = std::move(twins.twinCorners);
  twinnedPatches_ = twins.count;
}

SceneTracer::~SceneTracer() = default;

std::optional<SceneTracer::Hit> SceneTracer::intersect(Vec3 origin, Vec3 direction, double tNear,
                                                       double tFar) const {
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
  const RTCRay ray = rayHit.ray;  // the hit overwrites tfar
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(embree_->scene, &context, &rayHit);
  if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  // Embree's Ng has the orientation of Mesh::normal (tests/formfactor_sampling_test.cpp checks
  // it). Front or back as the batch below decides: in float, on the direction Embree saw.
  Hit hit{static_cast<int64_t>(rayHit.hit.primID),
          rayHit.ray.tfar,
          rayHit.hit.u,
          rayHit.hit.v,
          {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z}};
  if (ray.dir_x * rayHit.hit.Ng_x + ray.dir_y * rayHit.hit.Ng_y + ray.dir_z * rayHit.hit.Ng_z <
      0.0f) {
    return hit;
  }
  // The back of a face: the front of its twin, or of a face coincident with it otherwise.
  if (twin(hit.patch) >= 0) {
    twinBarycentrics(twinCorners_[hit.patch], hit.u, hit.v);
    hit.patch = twin_[hit.patch];
    hit.geometricNormal = -1.0 * hit.geometricNormal;
  } else if (const auto near = embree_->frontFaceNear(
                 ray, rayHit.ray.tfar, static_cast<float>(offset_[hit.patch]),
                 {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z})) {
    hit = {static_cast<int64_t>(near->hit.primID),
           near->ray.tfar,
           near->hit.u,
           near->hit.v,
           {near->hit.Ng_x, near->hit.Ng_y, near->hit.Ng_z}};
  }
  return hit;
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

  // Embree's Ng has the orientation of Mesh::normal. The back-face hits left (without a twin)
  // are counted: only they cost more.
  const size_t backHits =
      twin_.empty() ? readHits(rays, hits) : readHitsWithTwins(rays, hits, twin_, twinCorners_);
  if (backHits > 0) embree_->frontFacesNearBackHits(rays, hits, offset_);
}

}  // namespace radiosity::trace
