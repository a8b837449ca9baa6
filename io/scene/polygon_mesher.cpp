// Well-shaped triangles for a planar polygon of many corners: CGAL's constrained Delaunay
// triangulation of its outline, refined by points inside (never on its edges, which its
// neighbours share) until no triangle has an angle below ~20.7°, where the outline allows.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_criteria_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <queue>
#include <set>

#include "io/scene/polygon_mesher.h"

namespace radiosity::detail {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
/// The corner a CDT vertex is (-1: a point the refinement added).
struct CornerOf {
  int index = -1;
};
using Vb =
    CGAL::Triangulation_vertex_base_with_info_2<CornerOf, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_criteria_2<Cdt>;
using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria>;

/// Marks the faces inside the outline: those reached from outside across an odd number of its
/// edges (the mesher's own marking takes the whole convex hull).
void markInside(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->set_in_domain(false);
  std::queue<std::pair<Cdt::Face_handle, bool>> todo;
  std::set<Cdt::Face_handle> visited;
  todo.push({cdt.infinite_face(), false});
  visited.insert(cdt.infinite_face());
  while (!todo.empty()) {
    const auto [face, inside] = todo.front();
    todo.pop();
    face->set_in_domain(inside);
    for (int i = 0; i < 3; ++i) {
      const Cdt::Face_handle next = face->neighbor(i);
      if (!visited.insert(next).second) continue;
      todo.push({next, cdt.is_constrained({face, i}) ? !inside : inside});
    }
  }
}

/// Whether p lies inside the outline `ring` (crossing number; p is never on it here: a face's
/// centroid of a triangulation whose edges include the outline).
bool insideRing(const std::vector<PlanePoint>& ring, double x, double y) {
  bool inside = false;
  for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const auto [xi, yi] = ring[i];
    const auto [xj, yj] = ring[j];
    if ((yi > y) != (yj > y) && x < xj + (y - yj) * (xi - xj) / (yi - yj)) inside = !inside;
  }
  return inside;
}

// The triangulation refined to well-shaped triangles (the smallest angle's sin² 0.125:
// 20.7°) until it has `mostVertices`, and its triangles in the domain, each corner by its
// number: the first `numbered` are the caller's, the points added go after them in `added`.
PolygonTriangles refineAndCollect(Cdt& cdt, int numbered, size_t mostVertices) {
  Mesher mesher(cdt, Criteria(0.125));
  mesher.init(true);
  while (!mesher.is_refinement_done() && cdt.number_of_vertices() < mostVertices)
    mesher.step_by_step_refine_mesh();
  PolygonTriangles out;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::array<int, 3> triangle{};
    for (int k = 0; k < 3; ++k) {
      CornerOf& id = f->vertex(k)->info();
      if (id.index < 0) {
        id.index = numbered + static_cast<int>(out.added.size());
        const K::Point_2& p = f->vertex(k)->point();
        out.added.push_back({p.x(), p.y()});
      }
      triangle[k] = id.index;
    }
    out.triangles.push_back(triangle);
  }
  return out;
}

}  // namespace

std::optional<PolygonTriangles> meshPlanarRegion(const std::vector<std::vector<PlanePoint>>& rings,
                                                 size_t maxAdded) {
  try {
    Cdt cdt;
    int n = 0;
    std::vector<std::vector<Cdt::Vertex_handle>> corner(rings.size());
    for (size_t r = 0; r < rings.size(); ++r) {
      std::set<Cdt::Vertex_handle> own;
      for (const auto& [x, y] : rings[r]) {
        const Cdt::Vertex_handle h = cdt.insert(K::Point_2(x, y));
        if (!own.insert(h).second) return std::nullopt;  // a ring through one point twice
        if (h->info().index < 0) h->info().index = n;
        corner[r].push_back(h);
        ++n;
      }
    }
    const size_t points = cdt.number_of_vertices();
    for (const auto& ring : corner)
      for (size_t i = 0; i < ring.size(); ++i)
        cdt.insert_constraint(ring[i], ring[(i + 1) % ring.size()]);
    if (cdt.number_of_vertices() != points) return std::nullopt;  // edges that cross
    // Inside: within the outline and within no hole (parity would take a hole's overlap with
    // another, or its shared edges, wrongly).
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
      bool inside = !cdt.is_infinite(f);
      if (inside) {
        double x = 0, y = 0;
        for (int k = 0; k < 3; ++k) {
          x += f->vertex(k)->point().x() / 3;
          y += f->vertex(k)->point().y() / 3;
        }
        inside = insideRing(rings[0], x, y);
        for (size_t r = 1; inside && r < rings.size(); ++r) inside = !insideRing(rings[r], x, y);
      }
      f->set_in_domain(inside);
    }
    return refineAndCollect(cdt, n, points + maxAdded);
  } catch (const std::exception&) {  // CGAL's precondition failures on an odd outline
    return std::nullopt;
  }
}

std::optional<PolygonTriangles> meshPlanarPolygon(const std::vector<double>& u,
                                                  const std::vector<double>& v, size_t maxAdded) {
  const int n = static_cast<int>(u.size());
  try {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> corner(n);
    for (int i = 0; i < n; ++i) {
      corner[i] = cdt.insert(K::Point_2(u[i], v[i]));
      if (corner[i]->info().index >= 0) return std::nullopt;  // two corners at one point
      corner[i]->info().index = i;
    }
    for (int i = 0; i < n; ++i) cdt.insert_constraint(corner[i], corner[(i + 1) % n]);
    // An outline touching itself would have gained a vertex where its edges meet.
    if (cdt.number_of_vertices() != static_cast<size_t>(n)) return std::nullopt;
    markInside(cdt);
    PolygonTriangles out = refineAndCollect(cdt, n, n + maxAdded);
    if (out.triangles.size() != static_cast<size_t>(n) - 2 + 2 * out.added.size())
      return std::nullopt;  // not one disc (Euler): keep the ear clipper's answer
    return out;
  } catch (const std::exception&) {  // CGAL's precondition failures on an odd outline
    return std::nullopt;
  }
}

}  // namespace radiosity::detail
