// Conforming longest-edge refinement (Rivara). Each round marks the longest edge of every
// triangle that is too large, closes the marking (a triangle with any marked edge also marks its
// longest edge), then splits every marked edge in every triangle that has it: no T-junctions,
// and bisecting the longest edge first keeps the angles bounded away from 0.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "partition/partition.h"
#include "partition/surface_regions.h"

namespace radiosity::partition {

namespace {

struct EdgeTable {
  std::vector<std::array<int64_t, 3>> triangleEdges;  ///< edge k joins corners k and k+1
  std::vector<std::array<int64_t, 2>> endpoints;      ///< (smaller, larger) vertex index
  std::vector<int64_t> firstTriangle;                 ///< CSR: triangles of each edge
  std::vector<int64_t> triangles;
};

// Edges numbered in order of their vertex pair, so the numbering depends on the mesh only.
EdgeTable buildEdges(const Mesh& mesh) {
  const int64_t n = mesh.triangleCount();
  std::vector<std::pair<std::array<int64_t, 2>, int64_t>> corners;  // (edge, 3·triangle + k)
  corners.reserve(3 * n);
  for (int64_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      int64_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      corners.push_back({{std::min(a, b), std::max(a, b)}, 3 * t + k});
    }
  }
  std::sort(corners.begin(), corners.end());
  EdgeTable table;
  table.triangleEdges.resize(n);
  table.triangles.reserve(corners.size());
  for (size_t i = 0; i < corners.size(); ++i) {
    if (i == 0 || corners[i].first != corners[i - 1].first) {
      table.endpoints.push_back(corners[i].first);
      table.firstTriangle.push_back(static_cast<int64_t>(i));
    }
    int64_t edge = static_cast<int64_t>(table.endpoints.size()) - 1;
    table.triangleEdges[corners[i].second / 3][corners[i].second % 3] = edge;
    table.triangles.push_back(corners[i].second / 3);
  }
  table.firstTriangle.push_back(static_cast<int64_t>(corners.size()));
  return table;
}

double squaredLength(const Mesh& mesh, const std::array<int64_t, 2>& edge) {
  Vec3 d = mesh.vertices[edge[1]] - mesh.vertices[edge[0]];
  return dot(d, d);
}

// Relative difference under which two squared lengths, or two areas, count as equal. Scaling a
// scene by a decimal factor perturbs them by a few ulps (~1e-16 relative): far below this, so
// edges of equal length stay tied at any scale; real differences in a mesh are far above it.
constexpr double kTie = 1e-9;

// Which of the three edges is longest. Edges within kTie of the longest count as tied and go to
// the smallest edge number, so that the choice is deterministic and the same at any scale (the
// edge numbering depends on the mesh's connectivity only).
int longestEdge(const Mesh& mesh, const EdgeTable& edges, int64_t t) {
  std::array<double, 3> length;
  for (int k = 0; k < 3; ++k) {
    length[k] = squaredLength(mesh, edges.endpoints[edges.triangleEdges[t][k]]);
  }
  const double longest = std::max({length[0], length[1], length[2]});
  int best = -1;
  for (int k = 0; k < 3; ++k) {
    if (length[k] < longest * (1 - kTie)) continue;
    if (best < 0 || edges.triangleEdges[t][k] < edges.triangleEdges[t][best]) best = k;
  }
  return best;
}

// Orders the triangles `tooLarge` (ascending) largest area first. Areas within kTie of the
// first of a run of near-equal areas count as equal and keep the index order, so that rounding
// (e.g. from scaling the scene) cannot reorder triangles of equal area.
void sortLargestFirst(const Mesh& mesh, std::vector<int64_t>& tooLarge) {
  std::vector<double> area(tooLarge.size());
  for (size_t i = 0; i < tooLarge.size(); ++i) area[i] = mesh.area(tooLarge[i]);
  std::vector<size_t> order(tooLarge.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return area[a] > area[b]; });
  for (size_t first = 0; first < order.size();) {
    size_t end = first + 1;
    while (end < order.size() && area[order[end]] >= area[order[first]] * (1 - kTie)) ++end;
    std::sort(order.begin() + first, order.begin() + end);
    first = end;
  }
  std::vector<int64_t> sorted(tooLarge.size());
  for (size_t i = 0; i < order.size(); ++i) sorted[i] = tooLarge[order[i]];
  tooLarge = std::move(sorted);
}

// Appends triangle `t` of `from` to `to` with the given corners.
void appendTriangle(Mesh& to, const Mesh& from, int64_t t, const Triangle& corners) {
  to.triangles.push_back(corners);
  to.sourceFace.push_back(from.sourceFace[t]);
  to.reflectance.push_back(from.reflectance[t]);
  to.emission.push_back(from.emission[t]);
  if (from.hasLabels()) to.label.push_back(from.label[t]);
}

// Splits triangle t = (a, b, c) = `corners`, whose edge a-b is marked with midpoint m, and then
// the children's marked edges; `midpoints` holds those of a-b, b-c and c-a (m, midBC, midCA;
// -1: not marked). Children keep the parent's winding.
void splitTriangle(Mesh& out, const Mesh& in, int64_t t, const Triangle& corners,
                   const std::array<int64_t, 3>& midpoints) {
  const auto [a, b, c] = corners;
  const auto [m, midBC, midCA] = midpoints;
  auto emit = [&](int64_t p, int64_t q, int64_t r) { appendTriangle(out, in, t, {p, q, r}); };
  // Child (a, m, c) with original edge c-a; child (m, b, c) with original edge b-c.
  if (midCA >= 0) {
    emit(c, midCA, m);
    emit(midCA, a, m);
  } else {
    emit(a, m, c);
  }
  if (midBC >= 0) {
    emit(b, midBC, m);
    emit(midBC, c, m);
  } else {
    emit(m, b, c);
  }
}

// The midpoint made on edge (a, b), a < b, this round, or -1 (not split, or not an edge).
int64_t midpointOf(const EdgeTable& edges, const std::vector<int64_t>& midpoint, int64_t a,
                   int64_t b) {
  const auto found = std::lower_bound(edges.endpoints.begin(), edges.endpoints.end(),
                                      std::array<int64_t, 2>{a, b});
  if (found == edges.endpoints.end() || *found != std::array<int64_t, 2>{a, b}) return -1;
  return midpoint[found - edges.endpoints.begin()];
}

// The contact edges after a round: each split one replaced by its two halves, sorted.
ContactEdges halvesOf(const ContactEdges& contact, const EdgeTable& edges,
                      const std::vector<int64_t>& midpoint) {
  ContactEdges halves;
  for (const auto& [a, b] : contact) {
    const int64_t m = midpointOf(edges, midpoint, a, b);
    if (m < 0) {
      halves.push_back({a, b});
    } else {
      halves.push_back({std::min(a, m), std::max(a, m)});
      halves.push_back({std::min(m, b), std::max(m, b)});
    }
  }
  std::sort(halves.begin(), halves.end());
  return halves;
}

double longestSquared(const Mesh& mesh, int64_t t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    Vec3 d = mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k);
    longest = std::max(longest, dot(d, d));
  }
  return longest;
}

double aspectRatio(const Mesh& mesh, int64_t t) {
  return std::sqrt(3.0) * longestSquared(mesh, t) / (4.0 * mesh.area(t));
}

// A triangle whose longest edge squared exceeds this many times the area bound is split whatever
// its area. Well-shaped patches never reach it: halves of squares have 4 × their area, and an
// equilateral triangle 2.3 ×; a needle cut along a contact does.
constexpr double kNeedleShare = 8;

// Patches touching a contact line get this many times less area: B varies fastest there (the
// light falls off into the corner where a block stands on a floor or a wall meets it), and a
// patch along it averages the corner with the light beside it.
constexpr double kContactShare = 4;

// The edges along contact lines, as sorted (smaller, larger) vertex pairs; a split one is
// replaced by its halves after each round.
class ContactLines {
 public:
  explicit ContactLines(const ContactEdges* edges) : edges_(edges ? *edges : ContactEdges{}) {
    std::sort(edges_.begin(), edges_.end());
  }

  bool touches(const Mesh& mesh, int64_t t) const {
    if (edges_.empty()) return false;
    const Triangle& c = mesh.triangles[t];
    return has(c[0], c[1]) || has(c[1], c[2]) || has(c[2], c[0]);
  }

  void splitAt(const EdgeTable& edges, const std::vector<int64_t>& midpoint) {
    if (!edges_.empty()) edges_ = halvesOf(edges_, edges, midpoint);
  }

 private:
  bool has(int64_t a, int64_t b) const {
    return std::binary_search(edges_.begin(), edges_.end(),
                              std::array<int64_t, 2>{std::min(a, b), std::max(a, b)});
  }

  ContactEdges edges_;
};

// When a triangle is too large: its area above splitAbove, or, as a needle (a sliver of small
// area and long edges, as cuts along contacts can leave), its longest edge squared above
// kNeedleShare × splitAbove (a patch averages B over its whole extent, so its longest edge is
// bounded as well); both kContactShare times less along a contact line.
// `faceBound` (indexed by source face; empty: none) lowers the bound of a face's triangles.
struct SplitBound {
  SplitBound(double splitAbove, const ContactLines& contact, std::vector<double> faceBound = {})
      : splitAbove(splitAbove),
        longestAbove(kNeedleShare * splitAbove),
        contact(contact),
        faceBound(std::move(faceBound)) {}

  bool tooLarge(const Mesh& mesh, int64_t t) const {
    double share = contact.touches(mesh, t) ? 1 / kContactShare : 1;
    if (!faceBound.empty()) share = std::min(share, faceBound[mesh.sourceFace[t]] / splitAbove);
    return mesh.area(t) > share * splitAbove || longestSquared(mesh, t) > share * longestAbove;
  }

  double splitAbove, longestAbove;
  const ContactLines& contact;
  std::vector<double> faceBound;
};

// The fewest patches a surface's share may give it: below this, surfaces are so many that the
// area bound serves them (a city of 10^5 blocks).
constexpr int64_t kLeastSharePerSurface = 8;

// Per source face, the area bound that gives its smooth surface its equal part of `share`
// patches (share / surfaces), where that is below `maxArea`; empty when no surface needs it or
// the part is below kLeastSharePerSurface.
std::vector<double> smallSurfaceBounds(const Mesh& scene, double maxArea, int64_t share,
                                       const ContactEdges* contactEdges) {
  if (share <= 0 || !(maxArea > 0) || scene.triangleCount() == 0) return {};
  int64_t surfaces = 0;
  const std::vector<double> surface = smoothSurfaceAreas(scene, &surfaces, contactEdges);
  const int64_t least = share / std::max<int64_t>(surfaces, 1);
  if (least < kLeastSharePerSurface) return {};
  const int64_t faces = *std::max_element(scene.sourceFace.begin(), scene.sourceFace.end()) + 1;
  std::vector<double> bound(faces, maxArea);
  bool lowered = false;
  for (int64_t t = 0; t < scene.triangleCount(); ++t) {
    double& b = bound[scene.sourceFace[t]];
    const double part = surface[t] / static_cast<double>(least);
    if (part < b) b = part, lowered = true;
  }
  return lowered ? bound : std::vector<double>{};
}

// The edges to split this round: the longest edge of each triangle of `tooLarge`, in that
// order, each with the closure of its marking (a triangle with a marked edge marks its longest
// edge too), until the triangles the round will give reach `budget`. A triangle with m marked
// edges becomes 1 + m triangles, so every marked edge adds as many triangles as share it.
// `strict`: a triangle whose closure would take the count past `budget` is left whole, but for
// the first (the budget is a bound that a round splitting anything passes by at most one
// closure); else the last closure may pass it (the budget is a target).
std::vector<char> markEdges(const EdgeTable& edges, const std::vector<int>& longest,
                            const std::vector<int64_t>& tooLarge, int64_t triangles, int64_t budget,
                            bool strict = false) {
  std::vector<char> marked(edges.endpoints.size(), 0);
  std::vector<int64_t> work, closure;
  int64_t count = triangles;
  auto mark = [&](int64_t e) {
    if (marked[e]) return;
    marked[e] = 1;
    closure.push_back(e);
    count += edges.firstTriangle[e + 1] - edges.firstTriangle[e];
    for (int64_t i = edges.firstTriangle[e]; i < edges.firstTriangle[e + 1]; ++i) {
      work.push_back(edges.triangles[i]);
    }
  };
  for (int64_t t : tooLarge) {
    if (count >= budget) break;
    const int64_t before = count;
    closure.clear();
    mark(edges.triangleEdges[t][longest[t]]);
    while (!work.empty()) {
      int64_t u = work.back();
      work.pop_back();
      mark(edges.triangleEdges[u][longest[u]]);
    }
    if (strict && count > budget && before > triangles) {
      for (int64_t e : closure) marked[e] = 0;
      count = before;
      break;
    }
  }
  return marked;
}

// One midpoint per marked edge appended to the mesh's vertices, numbered in edge order; per
// edge, its midpoint or -1.
std::vector<int64_t> addMidpoints(Mesh& mesh, const EdgeTable& edges,
                                  const std::vector<char>& marked) {
  std::vector<int64_t> midpoint(edges.endpoints.size(), -1);
  for (size_t e = 0; e < edges.endpoints.size(); ++e) {
    if (!marked[e]) continue;
    midpoint[e] = static_cast<int64_t>(mesh.vertices.size());
    mesh.vertices.push_back(
        0.5 * (mesh.vertices[edges.endpoints[e][0]] + mesh.vertices[edges.endpoints[e][1]]));
  }
  return midpoint;
}

// The mesh with every triangle whose longest edge is marked split at its marked edges (the
// others as they are), each triangle's children in its place; it takes over the mesh's
// vertices, warnings and label names. `origin` (if not null): per new triangle, the old one.
Mesh splitMarked(Mesh& mesh, const EdgeTable& edges, const std::vector<int>& longest,
                 const std::vector<char>& marked, const std::vector<int64_t>& midpoint,
                 std::vector<int64_t>* origin = nullptr) {
  const int64_t n = mesh.triangleCount();
  Mesh next;
  next.triangles.reserve(2 * n);
  if (origin) origin->clear();
  for (int64_t t = 0; t < n; ++t) {
    if (origin) origin->resize(next.triangles.size(), t - 1);
    const Triangle& tri = mesh.triangles[t];
    int k = longest[t];
    int64_t e = edges.triangleEdges[t][k];
    if (!marked[e]) {
      appendTriangle(next, mesh, t, tri);
      continue;
    }
    int64_t midBC = midpoint[edges.triangleEdges[t][(k + 1) % 3]];
    int64_t midCA = midpoint[edges.triangleEdges[t][(k + 2) % 3]];
    splitTriangle(next, mesh, t, {tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]},
                  {midpoint[e], midBC, midCA});
  }
  if (origin) origin->resize(next.triangles.size(), n - 1);
  next.vertices = std::move(mesh.vertices);
  next.warnings = std::move(mesh.warnings);
  next.labelNames = std::move(mesh.labelNames);
  return next;
}

// One round of refinement within `budget` triangles (largest first when `limited`); false when
// no triangle is too large (the mesh is then unchanged).
bool refineRound(Mesh& mesh, const SplitBound& bound, ContactLines& contact, int64_t budget,
                 bool limited) {
  const int64_t n = mesh.triangleCount();
  // Nothing too large: done, without building the edge table (costly for 10⁷ triangles).
  std::vector<int64_t> tooLarge;
  for (int64_t t = 0; t < n; ++t)
    if (bound.tooLarge(mesh, t)) tooLarge.push_back(t);
  if (tooLarge.empty()) return false;
  if (limited) sortLargestFirst(mesh, tooLarge);
  const EdgeTable edges = buildEdges(mesh);
  std::vector<int> longest(n);
  for (int64_t t = 0; t < n; ++t) longest[t] = longestEdge(mesh, edges, t);
  const std::vector<char> marked = markEdges(edges, longest, tooLarge, n, budget);
  const std::vector<int64_t> midpoint = addMidpoints(mesh, edges, marked);
  contact.splitAt(edges, midpoint);
  mesh = splitMarked(mesh, edges, longest, marked, midpoint);
  return true;
}

void reportMeshing(MeshingReport& report, const Mesh& scene, const Mesh& mesh, double maxArea,
                   int rounds) {
  report.areaBound = maxArea > 0 ? maxArea : 0;
  report.inputTriangles = scene.triangleCount();
  report.patches = mesh.triangleCount();
  report.refinementRounds = rounds;
  report.maxPatchArea = 0;
  report.worstAspectRatio = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    report.maxPatchArea = std::max(report.maxPatchArea, mesh.area(t));
    report.worstAspectRatio = std::max(report.worstAspectRatio, aspectRatio(mesh, t));
  }
}

// refine() that stops splitting once the mesh has `budget` triangles: within a round the
// triangles above the bound are taken largest first (ties by index), each with the closure of
// its marking, until the count the round will give reaches the budget. A triangle is too large
// when its area exceeds maxArea·(1 + slack).
Mesh refineUpTo(const Mesh& scene, double maxArea, double slack, int64_t budget,
                MeshingReport* report, const ContactEdges* contactEdges, int64_t surfaceShare = 0) {
  Mesh mesh = scene;
  ContactLines contact(contactEdges);
  const SplitBound bound(maxArea * (1 + slack), contact,
                         smallSurfaceBounds(scene, maxArea, surfaceShare, contactEdges));
  const bool limited = budget < std::numeric_limits<int64_t>::max();
  int rounds = 0;
  while (maxArea > 0 && mesh.triangleCount() < budget &&
         refineRound(mesh, bound, contact, budget, limited))
    ++rounds;
  if (report) reportMeshing(*report, scene, mesh, maxArea, rounds);
  return mesh;
}

}  // namespace

Mesh refine(const Mesh& scene, double maxArea, MeshingReport* report,
            const ContactEdges* contactEdges, int64_t surfaceShare) {
  // The bound is the caller's: exact, so that every patch ends up with area <= maxArea.
  return refineUpTo(scene, maxArea, 0, std::numeric_limits<int64_t>::max(), report, contactEdges,
                    surfaceShare);
}

Mesh refineToCount(const Mesh& scene, int64_t target, MeshingReport* report,
                   const ContactEdges* contactEdges) {
  // With every patch at most A / target in area, at least target patches are needed, so this
  // bound always reaches the budget; the last round splits the largest patches first.
  // The bound derives from the scene's areas and may equal patch areas exactly (the box's, say);
  // a patch within kTie of it counts as small enough, so that rounding (e.g. from scaling the
  // scene) cannot decide whether it is split.
  const double bound = scene.triangleCount() < target ? scene.totalArea() / target : 0;
  return refineUpTo(scene, bound, kTie, target, report, contactEdges);
}

Mesh refineMarked(const Mesh& mesh, const std::vector<int64_t>& marked, int levels, int64_t budget,
                  std::vector<int64_t>* parentOf) {
  Mesh next = mesh;
  std::vector<int64_t> parent(mesh.triangleCount()), origin;
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int64_t> split = marked;  // this level's triangles to split, most urgent first
  for (int level = 0; level < levels && !split.empty() && next.triangleCount() < budget; ++level) {
    const int64_t n = next.triangleCount();
    const EdgeTable edges = buildEdges(next);
    std::vector<int> longest(n);
    for (int64_t t = 0; t < n; ++t) longest[t] = longestEdge(next, edges, t);
    const std::vector<char> marks = markEdges(edges, longest, split, n, budget, true);
    const std::vector<int64_t> midpoint = addMidpoints(next, edges, marks);
    next = splitMarked(next, edges, longest, marks, midpoint, &origin);
    // The next level splits the children of this level's triangles, in the same order.
    std::vector<int64_t> first(n + 1, 0);
    for (int64_t t : origin) ++first[t + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<int64_t> children;
    for (int64_t t : split)
      if (first[t + 1] - first[t] > 1)
        for (int64_t c = first[t]; c < first[t + 1]; ++c) children.push_back(c);
    split = std::move(children);
    for (int64_t& t : origin) t = parent[t];
    parent = origin;
  }
  if (parentOf) *parentOf = std::move(parent);
  return next;
}

}  // namespace radiosity::partition
