// trace: rays through the scene. An Embree BVH over the patches (Embree kept behind this
// header), shared by the form factors (formfactor/), the renderer (render/) and verify's path
// tracer (verify/); its random numbers and sample warps are trace/counter_rng.h and
// trace/sample_warps.h.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::trace {

/// The Embree library this program runs on (RTC_VERSION_STRING), for --version.
std::string embreeVersion();

/// An Embree BVH over every triangle of a mesh; the triangle index is the patch id.
/// Thread-safe for queries once built. Owns its Embree device and scene.
///
/// Thin two-sided surfaces: a wall or a leaf is often written as two coincident faces back to
/// back, each triangulated its own way (other diagonals, quads, other subdivisions), and Embree
/// returns whichever of two coincident triangles it meets first. So where a ray's first hit is
/// the back of a face, both queries below report the front of a face coincident with it
/// instead (its patch, distance, u, v and normal): such a surface has its full view factor from
/// either side, whatever the triangulation. That front is the hit's twin, where it has one (a
/// triangle on the same three positions, turned over: faces triangulated alike; paired when
/// built, a look-up), or else the nearest front face within offset() of the back-hit patch
/// from the hit along the ray (a second trace, of that short stretch). A back face with no front
/// that close is reported as it is (it absorbs); rays whose first hit is a front face, or
/// nothing, cost nothing more.
class SceneTracer {
 public:
  /// `threads` bounds the threads Embree builds the BVH with (0: all cores), so that ranks
  /// sharing a node do not oversubscribe it.
  explicit SceneTracer(const Mesh& mesh, int threads = 0);
  ~SceneTracer();
  SceneTracer(const SceneTracer&) = delete;
  SceneTracer& operator=(const SceneTracer&) = delete;

  struct Hit {
    int64_t patch;
    double distance;
    double u, v;  ///< barycentric coordinates of the hit: p = (1-u-v)·v0 + u·v1 + v·v2
    /// Not normalised, but pointing to the lit side like Mesh::normal: enough to tell front
    /// from back without looking the patch up.
    Vec3 geometricNormal;
  };
  /// The first triangle hit along origin + t·direction for t in (tNear, tFar), either side (a
  /// back only where no front coincides with it).
  std::optional<Hit> intersect(Vec3 origin, Vec3 direction, double tNear,
                               double tFar = 1e300) const;

  /// Many rays at once, as structure of arrays in float (as Embree takes them): the loop a
  /// form-factor row spends its time in, kept free of everything else.
  struct RayBatch {
    std::vector<float> originX, originY, originZ, directionX, directionY, directionZ, tFar;
    void resize(size_t n);
    /// Ray k: from `origin` along the unit `direction` up to `tFar` (< 0: idle).
    void set(size_t k, Vec3 origin, Vec3 direction, double tFar) {
      originX[k] = static_cast<float>(origin.x);
      originY[k] = static_cast<float>(origin.y);
      originZ[k] = static_cast<float>(origin.z);
      directionX[k] = static_cast<float>(direction.x);
      directionY[k] = static_cast<float>(direction.y);
      directionZ[k] = static_cast<float>(direction.z);
      this->tFar[k] = static_cast<float>(tFar);
    }
    size_t size() const { return tFar.size(); }
  };
  struct HitBatch {
    std::vector<int64_t> patch;   ///< -1: no hit
    std::vector<float> distance;  ///< along the (unit) direction
    std::vector<uint8_t> front;   ///< 1 where the ray met the lit side of the patch
    /// Working memory of the ray stream handed to Embree (reused from batch to batch).
    std::vector<float> tNear, time, normalX, normalY, normalZ, u, v;
    std::vector<unsigned> mask, id, flags, primitive, geometry, instance;
  };
  /// The first hit of every ray of the batch for t in (0, tFar), as the single ray's; a ray with
  /// tFar < 0 is idle.
  void intersect(const RayBatch& rays, HitBatch& hits) const;

  /// Length of the bounding box diagonal.
  double sceneSize() const { return sceneSize_; }

  /// How far rays start off `patch`'s surface, and how near along a ray a front face must lie
  /// to a back-face hit on `patch` to count as coincident with it: kCoincidentFaces ×
  /// sceneSize(), but at most kPatchShare of the patch's longest edge (a room on a ground plane
  /// 1e6 wide is 1e-6 of the scene: rays lifted by 1e-5 of it left the room) and at least
  /// kCoincidentFaces × the patch's distance from the centre, what float rounding there needs.
  double offset(int64_t patch) const { return offset_[patch]; }
  static constexpr double kPatchShare = 1e-2;

  /// Faces this close along a ray, in scene sizes, are coincident. Embree works in float: in the
  /// tracing frame (core/mesh.h: coordinates within ±0.5, where a float step is 3e-8 at most)
  /// two coincident faces' hit distances differ by a few steps divided by the cosine of
  /// incidence. 1e-5, some 300 steps, covers that to within about 0.6° of grazing, and is far
  /// thinner than any gap a model means (1 mm in a 100 m scene).
  static constexpr double kCoincidentFaces = 1e-5;

  /// The twin of `patch`, whose front a hit on the back of `patch` counts for, or -1 (of
  /// several, the one with the smallest id).
  int64_t twin(int64_t patch) const { return twin_.empty() ? -1 : twin_[patch]; }
  /// How many triangles have a twin (0 for most scenes).
  int64_t twinnedPatches() const { return twinnedPatches_; }

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;  ///< owned
  double sceneSize_ = 0;
  std::vector<double> offset_;  ///< per patch, offset()
  /// Per triangle its twin or -1, and which of its corners sit on the twin's corners 1 and 2
  /// (2 bits each), to carry u, v over; both empty when no triangle has a twin.
  std::vector<int64_t> twin_;
  std::vector<uint8_t> twinCorners_;
  int64_t twinnedPatches_ = 0;
};

}  // namespace radiosity::trace
