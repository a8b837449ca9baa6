// The Embree adapter: one device and one BVH over the patches, built once per rank.
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>

#include "formfactor/formfactor.h"
#include "io/core/error.h"

namespace radiosity::formfactor {

std::string embreeVersion() { return RTC_VERSION_STRING; }

namespace {

// Embree reports device errors through this callback; turn the next one into an exception.
void onEmbreeError(void* userPtr, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(userPtr);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
          (message ? message : "(no message)");
}

// ---- Twins: coincident triangles of opposite orientation ----

bool lexicographicLess(Vec3 a, Vec3 b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); }

// The corners of triangle t in lexicographic order of their positions; false when two corners
// sit on the same position (such a triangle has no orientation and no twin).
bool sortedCorners(const Mesh& mesh, int64_t t, std::array<int, 3>& order) {
  order = {0, 1, 2};
  auto less = [&](int a, int b) { return lexicographicLess(mesh.corner(t, a), mesh.corner(t, b)); };
  if (less(order[1], order[0])) std::swap(order[0], order[1]);
  if (less(order[2], order[1])) std::swap(order[1], order[2]);
  if (less(order[1], order[0])) std::swap(order[0], order[1]);
  return less(order[0], order[1]) && less(order[1], order[2]);
}

// 1 when `order` is an odd permutation of (0, 1, 2). Two triangles on the same three positions
// have the same orientation exactly when their sorted corner orders have the same parity.
int parity(const std::array<int, 3>& order) {
  return ((order[0] > order[1]) + (order[0] > order[2]) + (order[1] > order[2])) & 1;
}

uint64_t mix(uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  return h ^ (h >> 31);
}

// A hash of the set of triangle t's positions (0: degenerate, never a twin).
uint64_t positionHash(const Mesh& mesh, int64_t t) {
  std::array<int, 3> order;
  if (!sortedCorners(mesh, t, order)) return 0;
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (int k : order) {
    const Vec3 p = mesh.corner(t, k);
    for (double c : {p.x, p.y, p.z}) {
      c += 0.0;  // -0 and +0 are the same coordinate
      uint64_t bits;
      std::memcpy(&bits, &c, sizeof bits);
      h = mix(h + bits);
    }
  }
  return h == 0 ? 1 : h;
}

struct Twins {
  std::vector<int64_t> twin;         ///< empty when no triangle has one
  std::vector<uint8_t> twinCorners;  ///< corner of t on the twin's corner 1 | corner 2 << 2
  int64_t count = 0;
};

// Finds the twins of every triangle: same three positions (exactly), opposite orientation; of
// several, the one with the smallest id. Costs a hash per triangle and one sort of the hashes
// (8 bytes per triangle, freed on return); only triangles whose hash repeats are looked at
// further, so a scene without coincident triangles pays nothing else.
Twins findTwins(const Mesh& mesh) {
  const int64_t n = mesh.triangleCount();
  std::vector<uint64_t> repeated;
  {
    std::vector<uint64_t> hashes(n);
    for (int64_t t = 0; t < n; ++t) hashes[t] = positionHash(mesh, t);
    std::sort(hashes.begin(), hashes.end());
    for (int64_t i = 1; i < n; ++i) {
      if (hashes[i] != 0 && hashes[i] == hashes[i - 1] &&
          (repeated.empty() || repeated.back() != hashes[i])) {
        repeated.push_back(hashes[i]);
      }
    }
  }
  Twins twins;
  if (repeated.empty()) return twins;

  // The triangles whose hash repeats, ordered by hash, then exact sorted positions, then id.
  struct Candidate {
    uint64_t hash;
    int64_t triangle;
    std::array<int, 3> order;  ///< corners in lexicographic order of position
    Vec3 position(const Mesh& mesh, int k) const { return mesh.corner(triangle, order[k]); }
  };
  std::vector<Candidate> candidates;
  for (int64_t t = 0; t < n; ++t) {
    const uint64_t h = positionHash(mesh, t);
    if (h == 0 || !std::binary_search(repeated.begin(), repeated.end(), h)) continue;
    Candidate c{h, t, {}};
    sortedCorners(mesh, t, c.order);
    candidates.push_back(c);
  }
  // Strictly before in the order of places (equal places: the same three positions).
  auto placeLess = [&](const Candidate& a, const Candidate& b) {
    if (a.hash != b.hash) return a.hash < b.hash;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = a.position(mesh, k), q = b.position(mesh, k);
      if (lexicographicLess(p, q)) return true;
      if (lexicographicLess(q, p)) return false;
    }
    return false;
  };
  std::sort(candidates.begin(), candidates.end(), [&](const Candidate& a, const Candidate& b) {
    if (placeLess(a, b)) return true;
    if (placeLess(b, a)) return false;
    return a.triangle < b.triangle;
  });

  for (size_t first = 0; first < candidates.size();) {
    size_t end = first + 1;
    while (end < candidates.size() && !placeLess(candidates[first], candidates[end])) ++end;
    // The first (smallest id) of each orientation in the group [first, end).
    std::array<size_t, 2> firstOf = {end, end};
    for (size_t i = first; i < end; ++i) {
      const int side = parity(candidates[i].order);
      if (firstOf[side] == end) firstOf[side] = i;
    }
    if (firstOf[0] != end && firstOf[1] != end) {
      if (twins.twin.empty()) {
        twins.twin.assign(n, -1);
        twins.twinCorners.assign(n, 0);
      }
      for (size_t i = first; i < end; ++i) {
        const Candidate& c = candidates[i];
        const Candidate& other = candidates[firstOf[1 - parity(c.order)]];
        // The twin's corner other.order[k] sits on this triangle's corner c.order[k].
        std::array<int, 3> onTwin{};
        for (int k = 0; k < 3; ++k) onTwin[other.order[k]] = c.order[k];
        twins.twin[c.triangle] = other.triangle;
        twins.twinCorners[c.triangle] = static_cast<uint8_t>(onTwin[1] | onTwin[2] << 2);
        ++twins.count;
      }
    }
    first = end;
  }
  return twins;
}

// The barycentric coordinates of a hit on a triangle carried over to its twin, whose corners
// 1 and 2 sit on the triangle's corners `twinCorners & 3` and `twinCorners >> 2`.
template <typename Real>
void twinBarycentrics(uint8_t twinCorners, Real& u, Real& v) {
  const Real weight[3] = {1 - u - v, u, v};
  u = weight[twinCorners & 3];
  v = weight[(twinCorners >> 2) & 3];
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

  Twins twins = findTwins(mesh);
  twin_ = std::move(twins.twin);
  twinCorners_ = std::move(twins.twinCorners);
  twinnedPatches_ = twins.count;
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
  // Embree's Ng has the orientation of Mesh::normal (tests/formfactor_sampling_test.cpp checks
  // it).
  Hit hit{static_cast<int64_t>(rayHit.hit.primID),
          rayHit.ray.tfar,
          rayHit.hit.u,
          rayHit.hit.v,
          {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z}};
  // The back of a triangle with a twin is the front of the twin (the direction as Embree saw
  // it, in float, as the batch below decides).
  if (!twin_.empty() && twin_[hit.patch] >= 0 &&
      rayHit.ray.dir_x * rayHit.hit.Ng_x + rayHit.ray.dir_y * rayHit.hit.Ng_y +
              rayHit.ray.dir_z * rayHit.hit.Ng_z >
          0.0f) {
    twinBarycentrics(twinCorners_[hit.patch], hit.u, hit.v);
    hit.patch = twin_[hit.patch];
    hit.geometricNormal = -1.0 * hit.geometricNormal;
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

  if (twin_.empty()) {
    for (size_t k = 0; k < n; ++k) {
      const bool hit = hits.geometry[k] != RTC_INVALID_GEOMETRY_ID;
      hits.patch[k] = hit ? static_cast<int64_t>(hits.primitive[k]) : -1;
      // Embree's Ng has the orientation of Mesh::normal.
      hits.front[k] = hit && rays.directionX[k] * hits.normalX[k] +
                                     rays.directionY[k] * hits.normalY[k] +
                                     rays.directionZ[k] * hits.normalZ[k] <
                                 0.0f;
    }
    return;
  }
  // The same, and a hit on the back of a triangle with a twin becomes a hit on the twin's front.
  for (size_t k = 0; k < n; ++k) {
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
    if (facing > 0.0f && twin_[t] >= 0) {
      twinBarycentrics(twinCorners_[t], hits.u[k], hits.v[k]);
      hits.patch[k] = twin_[t];
      hits.front[k] = 1;
      hits.normalX[k] = -hits.normalX[k];
      hits.normalY[k] = -hits.normalY[k];
      hits.normalZ[k] = -hits.normalZ[k];
    }
  }
}

}  // namespace radiosity::formfactor
