// Faces laid over others (face_cover.h): the flat regions they belong to, and which lies over
// which.
#include "partition/face_cover.h"

#include <algorithm>

#include "partition/contact_finder.h"
#include "partition/surface_regions.h"

namespace radiosity::partition::contacts {

namespace {

// Per triangle, the area of its flat region: neighbours that lie in its plane and face the same
// way (exact predicates).
std::vector<double> flatRegionAreas(const Mesh& mesh) {
  return regionAreas(mesh, [&](int64_t s, int64_t t) {
    const Fast::Point_3 a = fastPoint(mesh.corner(s, 0)), b = fastPoint(mesh.corner(s, 1)),
                        c = fastPoint(mesh.corner(s, 2));
    for (int k = 0; k < 3; ++k)
      if (CGAL::orientation(a, b, c, fastPoint(mesh.corner(t, k))) != CGAL::COPLANAR) return false;
    return dot(mesh.normal(s), mesh.normal(t)) > 0;
  });
}

}  // namespace

FaceCover::FaceCover(const Mesh& mesh, const std::vector<std::pair<int64_t, int64_t>>& overlaps)
    : mesh_(mesh) {
  if (overlaps.empty()) return;
  const std::vector<double> region = flatRegionAreas(mesh);
  over_.resize(mesh.triangleCount());
  // Equal regions (within rounding of their sums): the later triangle lies over.
  auto liesOver = [&](int64_t u, int64_t t) {
    const double tolerance = 1e-12 * std::max(region[u], region[t]);
    if (std::abs(region[u] - region[t]) > tolerance) return region[u] < region[t];
    return u > t;
  };
  for (const auto& [s, t] : overlaps) {
    if (liesOver(s, t))
      over_[t].push_back(s);
    else
      over_[s].push_back(t);
  }
}

const std::vector<int64_t>& FaceCover::over(int64_t t) const {
  static const std::vector<int64_t> none;
  return over_.empty() ? none : over_[t];
}

int64_t FaceCover::coveringAt(int64_t t, const Vec3& point) const {
  for (int64_t u : over(t)) {
    const Chart2 chart(Fast::Triangle_3(fastPoint(mesh_.corner(u, 0)),
                                        fastPoint(mesh_.corner(u, 1)),
                                        fastPoint(mesh_.corner(u, 2))));
    const Fast::Point_2 a = chart(mesh_.corner(u, 0)), b = chart(mesh_.corner(u, 1)),
                        c = chart(mesh_.corner(u, 2)), p = chart(point);
    const CGAL::Orientation turn = CGAL::orientation(a, b, c);
    if (CGAL::orientation(a, b, p) == turn && CGAL::orientation(b, c, p) == turn &&
        CGAL::orientation(c, a, p) == turn)
      return u;
  }
  return -1;
}

}  // namespace radiosity::partition::contacts
