// Cuts every triangle along the lines where another triangle touches or crosses it, with CGAL's
// exact kernels: where a block rests on a floor that runs under it, the floor is cut along the
// block's walls, so that no patch straddles the lit floor and the floor under the block.
//
// 1. Candidate pairs of triangles whose boxes touch, plain neighbours left out (contact_finder.h).
// 2. Each pair that intersects (exact predicates) gives its intersection, constructed exactly:
//    a segment, or a polygon where the two are coplanar (coincident faces); a point of contact
//    separates nothing.
// 3. Each triangle with a cut across its inside is retriangulated in its own plane by a
//    constrained Delaunay triangulation with exact intersections, the cuts as constraints (cut
//    points within a rounding error of its corners and edges snapped onto them), and the pieces
//    are lifted back onto the plane, rounded to double once.
// Everything is exact up to that last rounding, so the same points come out in both triangles
// of a pair and on both sides of a shared edge, and the vertices weld.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>

#include "partition/contact_finder.h"
#include "partition/face_cover.h"
#include "partition/partition.h"

namespace radiosity::partition {

namespace {

using contacts::Cuts;
using contacts::Exact;
using Cdt =
    CGAL::Constrained_Delaunay_triangulation_2<Exact, CGAL::Default, CGAL::Exact_intersections_tag>;

/// A triangle's plane, seen along the axis its normal is largest in: points map to the other two
/// coordinates, in cyclic order, and back onto the plane exactly.
class PlaneChart {
 public:
  explicit PlaneChart(const Exact::Triangle_3& triangle) : origin_(triangle.vertex(0)) {
    normal_ = CGAL::cross_product(triangle.vertex(1) - origin_, triangle.vertex(2) - origin_);
    axis_ = 0;
    for (int k = 1; k < 3; ++k)
      if (CGAL::abs(normal_[k]) > CGAL::abs(normal_[axis_])) axis_ = k;
  }
  Exact::Point_2 down(const Exact::Point_3& p) const {
    return {p[(axis_ + 1) % 3], p[(axis_ + 2) % 3]};
  }
  Vec3 up(const Exact::Point_2& p) const {
    const int a = (axis_ + 1) % 3, b = (axis_ + 2) % 3;
    const Exact::FT along =
        origin_[axis_] -
        (normal_[a] * (p.x() - origin_[a]) + normal_[b] * (p.y() - origin_[b])) / normal_[axis_];
    Vec3 out;
    out[axis_] = CGAL::to_double(along);
    out[a] = CGAL::to_double(p.x());
    out[b] = CGAL::to_double(p.y());
    return out;
  }
  /// Whether the chart turns the triangle's winding over.
  bool mirrors() const { return CGAL::is_negative(normal_[axis_]); }

 private:
  Exact::Point_3 origin_;
  Exact::Vector_3 normal_;
  int axis_ = 0;
};

// A cut point within `tolerance` of the triangle's corner is that corner, and within it of an
// edge lies on that edge: where a user's floor was cut by hand to a block's slanted wall in
// double, its edge and the wall's foot are two lines 1e-13 apart, and cutting along both would
// leave slivers that rounding flattens to nothing.
Exact::Point_3 snap(const Exact::Triangle_3& triangle, const Exact::Point_3& p,
                    const Exact::FT& squaredTolerance) {
  for (int k = 0; k < 3; ++k)
    if (CGAL::squared_distance(p, triangle.vertex(k)) <= squaredTolerance)
      return triangle.vertex(k);
  for (int k = 0; k < 3; ++k) {
    const Exact::Segment_3 edge(triangle.vertex(k), triangle.vertex((k + 1) % 3));
    if (CGAL::squared_distance(p, edge) <= squaredTolerance)
      return edge.supporting_line().projection(p);
  }
  return p;
}

// Whether the segment a–b lies on one of the triangle's edges.
bool alongAnEdge(const Exact::Triangle_3& triangle, const Exact::Point_3& a,
                 const Exact::Point_3& b) {
  for (int k = 0; k < 3; ++k) {
    const Exact::Point_3& p = triangle.vertex(k);
    const Exact::Point_3& q = triangle.vertex((k + 1) % 3);
    if (CGAL::collinear(p, q, a) && CGAL::collinear(p, q, b)) return true;
  }
  return false;
}

// The pieces of triangle t cut along `cuts`, each as three positions wound as t is.
std::vector<std::array<Vec3, 3>> cutTriangle(const Exact::Triangle_3& triangle, const Cuts& cuts,
                                             double tolerance) {
  const PlaneChart chart(triangle);
  const Exact::FT squaredTolerance = Exact::FT(tolerance) * Exact::FT(tolerance);
  Cdt cdt;
  for (int k = 0; k < 3; ++k) cdt.insert(chart.down(triangle.vertex(k)));
  // Only cuts that cross the triangle's inside: one along its own edge (a wall's foot on a floor,
  // seen from the wall) or through a single point (a corner touching it) separates nothing,
  // and splitting the edge there would fan the triangle into needles from its far corner.
  for (const Exact::Segment_3& s : cuts.segments) {
    const Exact::Point_3 a = snap(triangle, s.source(), squaredTolerance),
                         b = snap(triangle, s.target(), squaredTolerance);
    if (a != b && !alongAnEdge(triangle, a, b)) cdt.insert_constraint(chart.down(a), chart.down(b));
  }

  std::vector<std::array<Vec3, 3>> pieces;
  for (auto face = cdt.finite_faces_begin(); face != cdt.finite_faces_end(); ++face) {
    std::array<Vec3, 3> piece;
    for (int k = 0; k < 3; ++k) piece[k] = chart.up(face->vertex(k)->point());
    if (chart.mirrors()) std::swap(piece[1], piece[2]);  // the CDT's faces turn counter-clockwise
    pieces.push_back(piece);
  }
  // The CDT's face order follows its memory; the mesh's must follow the geometry only.
  auto key = [](const std::array<Vec3, 3>& p) {
    const Vec3 c = (1.0 / 3) * (p[0] + p[1] + p[2]);
    return std::array<double, 3>{c.x, c.y, c.z};
  };
  std::sort(pieces.begin(), pieces.end(),
            [&](const auto& a, const auto& b) { return key(a) < key(b); });
  return pieces;
}

double area(const std::array<Vec3, 3>& p) { return 0.5 * length(cross(p[1] - p[0], p[2] - p[0])); }

// Adds `area` of triangle t, covered by triangle u, to the report's entry for their faces.
void addCovered(const Mesh& scene, int64_t t, int64_t u, double area,
                std::map<std::pair<int64_t, int64_t>, CoveredFace>& covered) {
  CoveredFace& entry = covered[{scene.sourceFace[t], scene.sourceFace[u]}];
  entry.face = scene.sourceFace[t];
  entry.by = scene.sourceFace[u];
  if (scene.hasLabels()) entry.label = scene.label[t], entry.byLabel = scene.label[u];
  entry.area += area;
}

}  // namespace

Mesh cutAtContacts(const Mesh& scene, ContactReport* report, const ContactProgress& progress) {
  ContactReport local;
  const double tolerance = contacts::snapTolerance(scene);
  contacts::ContactFinder finder(scene, tolerance);
  std::vector<std::pair<int64_t, int64_t>> overlaps;  // one face laid over another
  const std::vector<std::pair<int64_t, int64_t>> pairs = finder.candidatePairs(&overlaps);
  local.candidatePairs = static_cast<int64_t>(pairs.size());
  std::map<int64_t, Cuts> cuts;
  for (size_t k = 0; k < pairs.size(); ++k) {
    finder.intersect(pairs[k].first, pairs[k].second, cuts, overlaps);
    if (progress && k % 4096 == 4095)
      progress("pairs of triangles whose boxes touch intersected", static_cast<int64_t>(k + 1),
               local.candidatePairs);
  }

  const contacts::FaceCover cover(scene, overlaps);
  std::map<std::pair<int64_t, int64_t>, CoveredFace> covered;

  Mesh out;
  out.vertices = scene.vertices;
  out.labelNames = scene.labelNames;
  out.warnings = scene.warnings;
  out.lengthUnit = scene.lengthUnit;
  // The pieces' corners by position: the corners of every triangle cut (so that a cut through
  // another triangle's corner, as a wall's foot on a floor, reuses it and the pieces stay joined
  // to their uncut neighbours), then the new points.
  std::map<std::array<double, 3>, int64_t> vertexAt;
  for (const auto& [t, unused] : cuts) {
    for (int64_t v : scene.triangles[t]) {
      const Vec3& p = scene.vertices[v];
      vertexAt.emplace(std::array<double, 3>{p.x, p.y, p.z}, v);
    }
  }
  const size_t original = vertexAt.size();
  for (int64_t t = 0; t < scene.triangleCount(); ++t) {
    if (progress && t % 65536 == 65535) progress("triangles cut", t + 1, scene.triangleCount());
    auto keep = [&](const Triangle& triangle) {
      out.triangles.push_back(triangle);
      out.sourceFace.push_back(scene.sourceFace[t]);
      out.reflectance.push_back(scene.reflectance[t]);
      out.emission.push_back(scene.emission[t]);
      if (scene.hasLabels()) out.label.push_back(scene.label[t]);
    };
    // A whole triangle under another is left out.
    auto keepUnlessCovered = [&]() {
      const int64_t u = cover.coveringAt(t, scene.centroid(t));
      if (u < 0)
        keep(scene.triangles[t]);
      else
        addCovered(scene, t, u, scene.area(t), covered);
    };
    const auto found = cuts.find(t);
    if (found == cuts.end()) {
      keepUnlessCovered();
      continue;
    }
    const std::vector<std::array<Vec3, 3>> pieces =
        cutTriangle(finder.exactTriangle(t), found->second, tolerance);
    if (pieces.size() <= 1) {  // touched only along its own edges or at its corners
      keepUnlessCovered();
      continue;
    }
    ++local.trianglesCut;
    for (const std::array<Vec3, 3>& piece : pieces) {
      if (!(area(piece) > 0)) continue;  // a sliver that rounding to double flattened
      // Pieces are whole cells of the overlaps' outlines: each lies under a face or beside it.
      const int64_t u = cover.coveringAt(t, (1.0 / 3) * (piece[0] + piece[1] + piece[2]));
      if (u >= 0) {
        addCovered(scene, t, u, area(piece), covered);
        continue;
      }
      Triangle triangle;
      for (int k = 0; k < 3; ++k) {
        const std::array<double, 3> key{piece[k].x, piece[k].y, piece[k].z};
        auto [it, inserted] = vertexAt.emplace(key, static_cast<int64_t>(out.vertices.size()));
        if (inserted) out.vertices.push_back(piece[k]);
        triangle[k] = it->second;
      }
      keep(triangle);
      ++local.pieces;
    }
  }
  local.verticesAdded = static_cast<int64_t>(vertexAt.size() - original);
  for (const auto& [faces, entry] : covered) {
    local.covered.push_back(entry);
    local.coveredArea += entry.area;
  }
  if (report) *report = local;
  return out;
}

}  // namespace radiosity::partition
