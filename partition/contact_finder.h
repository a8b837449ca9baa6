// Private to partition/: finding where triangles touch or cross (contacts), with CGAL's exact
// kernels, for cutAtContacts() (contact_cuts.cpp) and contactEdges() (contact_edges.cpp).
// Candidate pairs are the triangles whose boxes touch (CGAL's box intersection, closed boxes
// widened by the snapping tolerance); neighbours in a mesh meet along the edges and corners they
// share, which needs no cut, so pairs sharing an edge or a corner are skipped unless exact
// orientation tests say they overlap or cross beyond it. Vertices are recognised by position,
// so a soup of unshared vertices is the same as an indexed mesh.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include "partition/partition.h"

namespace radiosity::partition::contacts {

using Fast = CGAL::Exact_predicates_inexact_constructions_kernel;  // exact predicates
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;   // exact constructions
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int64_t>;

// One id per distinct vertex position, so that neighbours are recognised whether or not the file
// shares their vertices.
inline std::vector<int64_t> positionIds(const Mesh& mesh) {
  const int64_t n = static_cast<int64_t>(mesh.vertices.size());
  std::vector<int64_t> order(n);
  for (int64_t i = 0; i < n; ++i) order[i] = i;
  auto key = [&](int64_t i) {
    const Vec3& p = mesh.vertices[i];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
  std::vector<int64_t> id(n);
  for (int64_t k = 0; k < n; ++k)
    id[order[k]] = k > 0 && key(order[k]) == key(order[k - 1]) ? id[order[k - 1]] : order[k];
  return id;
}

// Cut points this share of the scene's size from a triangle's corner or edge are snapped onto
// it: far above the rounding of coordinates (1e-16), far below any feature that matters to light.
constexpr double kSnapShare = 1e-9;

// cos 30°: surfaces meeting at a smaller angle between their normals are one smooth surface.
constexpr double kCreaseCosine = 0.8660254037844387;

inline double snapTolerance(const Mesh& mesh) {
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  return kSnapShare * length(hi - lo);
}

inline Fast::Point_3 fastPoint(const Vec3& p) { return {p.x, p.y, p.z}; }
inline Exact::Point_3 exactPoint(const Vec3& p) { return {p.x, p.y, p.z}; }

/// What a triangle is to be cut along: segments on it, exact.
struct Cuts {
  std::vector<Exact::Segment_3> segments;
};

/// The plane of a triangle seen along the axis its normal is largest in, for exact orientation
/// tests in 2D: dropping a coordinate of a double point is exact.
class Chart2 {
 public:
  explicit Chart2(const Fast::Triangle_3& triangle) {
    const Fast::Vector_3 n =
        CGAL::normal(triangle.vertex(0), triangle.vertex(1), triangle.vertex(2));
    for (int k = 1; k < 3; ++k)
      if (std::abs(n[k]) > std::abs(n[axis_])) axis_ = k;
  }
  Fast::Point_2 operator()(const Vec3& p) const { return {p[(axis_ + 1) % 3], p[(axis_ + 2) % 3]}; }

 private:
  int axis_ = 0;
};

/// The pairs of triangles of a mesh that touch, and what they meet along. Holds `mesh` (not
/// owned) and an id per vertex position.
class ContactFinder {
 public:
  /// `tolerance`: how near a point counts as on a triangle (contact edges), and how far boxes
  /// are widened for them so that such near contacts are candidates at all.
  ContactFinder(const Mesh& mesh, double tolerance)
      : mesh_(mesh), position_(positionIds(mesh)), tolerance_(tolerance) {}

  /// Calls visit(s, t) for every pair of triangles whose boxes touch (closed boxes, `widened`
  /// by the tolerance or by a few ulps only), s < t, in an order that is CGAL's affair.
  template <class Visit>
  void touchingPairs(bool widened, Visit visit) const {
    const double widen = widened ? tolerance_ : 0;
    std::vector<Box> boxes;
    boxes.reserve(mesh_.triangles.size());
    for (int64_t t = 0; t < mesh_.triangleCount(); ++t) {
      if (degenerate(t)) continue;
      CGAL::Bbox_3 box = fastPoint(mesh_.corner(t, 0)).bbox() +
                         fastPoint(mesh_.corner(t, 1)).bbox() +
                         fastPoint(mesh_.corner(t, 2)).bbox();
      box.dilate(1);  // a few ulps, so that boxes touching after rounding are still pairs
      box = CGAL::Bbox_3(box.xmin() - widen, box.ymin() - widen, box.zmin() - widen,
                         box.xmax() + widen, box.ymax() + widen, box.zmax() + widen);
      boxes.emplace_back(box, t);
    }
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
      visit(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
    });
  }

  /// Every pair (s < t) of triangles whose boxes touch and that are not plain neighbours, sorted.
  /// Boxes not widened: a cut needs the triangles to meet (exact predicates decide), and widened
  /// boxes of a flat floor would pair it with its neighbours' neighbours, each pair coplanar,
  /// where the filtered predicates fall back to exact arithmetic (most of the time at 10^6).
  /// `duplicates`, if given, gets the pairs that are one triangle twice, facing the same way
  /// (nothing to cut, but one lies over the other), sorted.
  std::vector<std::pair<int64_t, int64_t>> candidatePairs(
      std::vector<std::pair<int64_t, int64_t>>* duplicates = nullptr) const {
    std::vector<std::pair<int64_t, int64_t>> pairs;
    touchingPairs(false, [&](int64_t s, int64_t t) {
      if (mayCross(s, t))
        pairs.emplace_back(s, t);
      else if (duplicates && sameCornersSameSide(s, t))
        duplicates->emplace_back(s, t);
    });
    std::sort(pairs.begin(), pairs.end());
    if (duplicates) std::sort(duplicates->begin(), duplicates->end());
    return pairs;
  }

  /// Adds the edges of s and t that lie along the line where they meet to `edges`, when they
  /// meet along a line at a concave angle: each has a corner in front of the other's plane (a
  /// block's wall and the floor around it, a room's wall and floor; not a block's wall and its
  /// top).
  void addConcaveContact(int64_t s, int64_t t, ContactEdges& edges) const {
    // Facets of one curved surface (a sphere seen from inside) meet at concave angles too, but
    // B is smooth across them: only a crease counts, as smooth shading draws it (30°).
    if (dot(mesh_.normal(s), mesh_.normal(t)) > kCreaseCosine) return;
    if (!inFrontOf(s, t) || !inFrontOf(t, s)) return;
    // An edge of one lies along the line when both its ends lie on the other triangle, to the
    // snapping tolerance (so that a floor cut by hand in double, 1e-13 off a slanted wall's
    // foot, counts; and the same at any scale, which exact tests on rounded input are not).
    const Fast::FT squaredTolerance = tolerance_ * tolerance_;
    for (const auto& [triangle, other] : {std::pair{s, t}, std::pair{t, s}}) {
      const Fast::Triangle_3 on = fastTriangle(other);
      for (int k = 0; k < 3; ++k) {
        const int64_t a = mesh_.triangles[triangle][k], b = mesh_.triangles[triangle][(k + 1) % 3];
        if (CGAL::squared_distance(fastPoint(mesh_.vertices[a]), on) <= squaredTolerance &&
            CGAL::squared_distance(fastPoint(mesh_.vertices[b]), on) <= squaredTolerance)
          edges.push_back({std::min(a, b), std::max(a, b)});
      }
    }
  }

  /// Adds what triangles s and t cut each other along to `cuts`; and the pair to `overlaps` when
  /// they are coplanar, face the same way and overlap with an area (one laid over the other).
  void intersect(int64_t s, int64_t t, std::map<int64_t, Cuts>& cuts,
                 std::vector<std::pair<int64_t, int64_t>>& overlaps) const {
    if (!CGAL::do_intersect(fastTriangle(s), fastTriangle(t))) return;
    const auto result = CGAL::intersection(exactTriangle(s), exactTriangle(t));
    if (!result) return;
    auto add = [&](auto&& addTo) {
      addTo(cuts[s]);
      addTo(cuts[t]);
    };
    // A single point of contact (a corner touching a face) separates nothing: not cut.
    if (const auto* segment = boost::get<Exact::Segment_3>(&*result)) {
      add([&](Cuts& c) { c.segments.push_back(*segment); });
    } else if (const auto* triangle = boost::get<Exact::Triangle_3>(&*result)) {
      if (sameSide(s, t)) overlaps.emplace_back(s, t);
      for (int k = 0; k < 3; ++k) {
        const Exact::Segment_3 edge(triangle->vertex(k), triangle->vertex((k + 1) % 3));
        add([&](Cuts& c) { c.segments.push_back(edge); });
      }
    } else if (const auto* polygon = boost::get<std::vector<Exact::Point_3>>(&*result)) {
      if (sameSide(s, t)) overlaps.emplace_back(s, t);
      for (size_t k = 0; k < polygon->size(); ++k) {
        const Exact::Segment_3 edge((*polygon)[k], (*polygon)[(k + 1) % polygon->size()]);
        add([&](Cuts& c) { c.segments.push_back(edge); });
      }
    }
  }

  Fast::Triangle_3 fastTriangle(int64_t t) const {
    return {fastPoint(mesh_.corner(t, 0)), fastPoint(mesh_.corner(t, 1)),
            fastPoint(mesh_.corner(t, 2))};
  }
  Exact::Triangle_3 exactTriangle(int64_t t) const {
    return {exactPoint(mesh_.corner(t, 0)), exactPoint(mesh_.corner(t, 1)),
            exactPoint(mesh_.corner(t, 2))};
  }
  bool degenerate(int64_t t) const { return fastTriangle(t).is_degenerate(); }

  /// Whether coplanar triangles s and t face the same way.
  bool sameSide(int64_t s, int64_t t) const { return dot(mesh_.normal(s), mesh_.normal(t)) > 0; }

 private:
  // Neighbours in a mesh meet only along the edge or at the corner they share, and are not cut.
  // They overlap or cross all the same when they lie in one plane on the same side of their
  // shared edge or corner (coincident faces triangulated differently), or when, sharing a corner
  // only, each reaches the other's plane beyond it (a wall's foot through a floor's corner).
  bool mayCross(int64_t s, int64_t t) const {
    int shared = 0;
    std::array<int, 2> onS{}, onT{};  // the shared corners' positions in s and in t
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (position_[mesh_.triangles[s][i]] == position_[mesh_.triangles[t][j]] && shared < 2) {
          onS[shared] = i, onT[shared] = j;
          ++shared;
        } else if (position_[mesh_.triangles[s][i]] == position_[mesh_.triangles[t][j]]) {
          return false;  // three shared corners: the same triangle (twins, or a duplicate)
        }
      }
    }
    if (shared == 0) return true;
    const bool coplanar = side(s, mesh_.corner(t, 0)) == CGAL::COPLANAR &&
                          side(s, mesh_.corner(t, 1)) == CGAL::COPLANAR &&
                          side(s, mesh_.corner(t, 2)) == CGAL::COPLANAR;
    if (shared == 2) {
      if (!coplanar) return false;
      const int apexS = 3 - onS[0] - onS[1], apexT = 3 - onT[0] - onT[1];
      const Chart2 chart(fastTriangle(s));
      const Fast::Point_2 a = chart(mesh_.corner(s, onS[0])), b = chart(mesh_.corner(s, onS[1]));
      return CGAL::orientation(a, b, chart(mesh_.corner(s, apexS))) ==
             CGAL::orientation(a, b, chart(mesh_.corner(t, apexT)));
    }
    if (coplanar) return sectorsOverlap(s, onS[0], t, onT[0]);
    return reachesPlane(s, onS[0], t) && reachesPlane(t, onT[0], s);
  }

  // The same three corners (by position), facing the same way: one triangle given twice.
  bool sameCornersSameSide(int64_t s, int64_t t) const {
    for (int i = 0; i < 3; ++i) {
      const int64_t p = position_[mesh_.triangles[s][i]];
      if (p != position_[mesh_.triangles[t][0]] && p != position_[mesh_.triangles[t][1]] &&
          p != position_[mesh_.triangles[t][2]])
        return false;
    }
    return !degenerate(s) && sameSide(s, t);
  }

  CGAL::Orientation side(int64_t plane, const Vec3& p) const {
    return CGAL::orientation(fastPoint(mesh_.corner(plane, 0)), fastPoint(mesh_.corner(plane, 1)),
                             fastPoint(mesh_.corner(plane, 2)), fastPoint(p));
  }

  // Whether a corner of triangle `b` lies strictly in front of triangle `a`'s plane (its lit side).
  bool inFrontOf(int64_t a, int64_t b) const {
    for (int k = 0; k < 3; ++k)
      if (side(a, mesh_.corner(b, k)) == CGAL::POSITIVE) return true;
    return false;
  }

  // Whether triangle `a`, apart from its corner `corner`, reaches the plane of triangle `b` (a
  // corner on it, or corners on both sides of it).
  bool reachesPlane(int64_t a, int corner, int64_t b) const {
    const auto side1 = side(b, mesh_.corner(a, (corner + 1) % 3));
    const auto side2 = side(b, mesh_.corner(a, (corner + 2) % 3));
    return side1 != side2 || side1 == CGAL::COPLANAR;
  }

  // Coplanar triangles s and t with one shared corner: whether their angles at that corner
  // overlap (a fan of a flat floor does not; a face under a differently subdivided twin does).
  bool sectorsOverlap(int64_t s, int cornerS, int64_t t, int cornerT) const {
    const Chart2 chart(fastTriangle(s));
    const Fast::Point_2 v = chart(mesh_.corner(s, cornerS));
    auto rays = [&](int64_t triangle, int corner) {
      std::array<Fast::Point_2, 2> r = {chart(mesh_.corner(triangle, (corner + 1) % 3)),
                                        chart(mesh_.corner(triangle, (corner + 2) % 3))};
      if (CGAL::orientation(v, r[0], r[1]) == CGAL::RIGHT_TURN) std::swap(r[0], r[1]);
      return r;
    };
    const auto a = rays(s, cornerS), b = rays(t, cornerT);
    auto inside = [&](const std::array<Fast::Point_2, 2>& sector, const Fast::Point_2& p) {
      return CGAL::orientation(v, sector[0], p) == CGAL::LEFT_TURN &&
             CGAL::orientation(v, p, sector[1]) == CGAL::LEFT_TURN;
    };
    // On one ray from v: collinear, and on the same side of v in both coordinates.
    auto along = [&](const Fast::Point_2& p, const Fast::Point_2& q) {
      return CGAL::orientation(v, p, q) == CGAL::COLLINEAR &&
             CGAL::compare(p.x(), v.x()) == CGAL::compare(q.x(), v.x()) &&
             CGAL::compare(p.y(), v.y()) == CGAL::compare(q.y(), v.y());
    };
    return inside(a, b[0]) || inside(a, b[1]) || inside(b, a[0]) || inside(b, a[1]) ||
           (along(a[0], b[0]) && along(a[1], b[1]));
  }

  const Mesh& mesh_;
  std::vector<int64_t> position_;
  double tolerance_;
};

}  // namespace radiosity::partition::contacts
