// partition: turns the scene's triangles into patches (cut along contacts, then conforming
// refinement to an area bound),
// gives each patch its global id (ordered along a space-filling curve) and splits the ids into
// one contiguous block per rank. Pure functions of the scene and the options: the same on
// every rank and for any number of ranks.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"

namespace radiosity::partition {

struct MeshingReport {
  int64_t inputTriangles = 0;
  int64_t patches = 0;
  int refinementRounds = 0;
  double areaBound = 0;  ///< the bound refined to; 0 when none
  double maxPatchArea = 0;
  double worstAspectRatio = 0;  ///< √3·(longest edge)² / (4·area): 1 for equilateral
};

/// Edges as (smaller, larger) vertex index pairs.
using ContactEdges = std::vector<std::array<int64_t, 2>>;

/// A face covered by another laid over it (coplanar, facing the same way), whose covered part
/// cutAtContacts() left out.
struct CoveredFace {
  int64_t face = 0;    ///< the covered face (0-based input face, Mesh::sourceFace)
  int64_t by = 0;      ///< the face over it
  int32_t label = -1;  ///< the covered face's label (Mesh::label), -1 without labels
  int32_t byLabel = -1;
  double area = 0;  ///< of `face` left out under `by`, in the scene's units
};

/// What cutAtContacts() found and did.
struct ContactReport {
  int64_t candidatePairs = 0;  ///< pairs of triangles whose boxes touch, neighbours left out
  int64_t trianglesCut = 0;    ///< triangles replaced by pieces
  int64_t pieces = 0;          ///< the pieces they became
  int64_t verticesAdded = 0;
  std::vector<CoveredFace> covered;  ///< by (face, by)
  double coveredArea = 0;            ///< their sum
};

/// Cuts every triangle along the lines where another triangle touches, rests on or passes
/// through it (a block standing on a floor that runs under it, a wall through a floor, two
/// coincident faces triangulated differently, which come out triangulated alike), so that no
/// patch straddles a contact: the floor under a block becomes patches of its own, which see
/// nothing. Exact predicates and constructions (CGAL), rounded to double once, so the pieces
/// of both triangles of a contact and of both sides of a shared edge meet at the same vertices.
/// Neighbours meeting only along the edges and corners they share are not cut. A cut triangle is
/// replaced, in its place in the order, by its pieces (the same winding, sourceFace, material
/// and label); uncut triangles and all input vertices keep their indices. A face laid over
/// another (coplanar, facing the same way, overlapping: a poster on a wall, a lamp panel flush on
/// a ceiling, a room's floor on the ground) covers it: the covered pieces are left out (the
/// smaller flat region lies over the larger; of equal ones the later face), and
/// report->covered says which. Deterministic: the same
/// on every rank. `progress`, if given, is called now and then with what is being done (the
/// candidate pairs intersected, the triangles cut), how much of it is done and its whole: on
/// 3·10^6 triangles this takes 40 s.
using ContactProgress = std::function<void(const char* what, int64_t done, int64_t whole)>;
Mesh cutAtContacts(const Mesh& scene, ContactReport* report = nullptr,
                   const ContactProgress& progress = {});

/// The edges that lie along contact lines, where two triangles meet along a line at a concave
/// angle, each in front of the other (a block's wall and the floor it stands on, a room's wall
/// and floor, whether or not they share the edge; not a block's top and its wall): (smaller,
/// larger) vertex index pairs, sorted. Exact predicates.
ContactEdges contactEdges(const Mesh& mesh);

/// Splits longest edges until every triangle has area ≤ maxArea and longest edge² ≤ 8 maxArea
/// (needles are split too; well-shaped triangles meet the first bound first), no refinement when
/// maxArea ≤ 0. Conforming: an edge split in one triangle is split in every triangle sharing
/// it, so no T-junctions appear. Triangles keep their sourceFace and material.
/// With `contactEdges` (contactEdges() of `scene`), patches with an edge along a contact line
/// are refined to a quarter of the bound, where B varies fastest. `surfaceShare` > 0: that many
/// patches are shared equally among the smooth surfaces (triangles joined along edges, normals
/// within 30°: a wall, a sphere), each refined to at most its area / its part, so that a room on
/// a ground of 10^6 m² gets patches where its light varies (the bound alone gives its walls 2
/// triangles each); not when the parts would be below 8 patches (so many surfaces that the
/// bound serves them).
Mesh refine(const Mesh& scene, double maxArea, MeshingReport* report = nullptr,
            const ContactEdges* contactEdges = nullptr, int64_t surfaceShare = 0);

/// Refines to about `target` patches (none when the scene has that many already): the bound
/// A / target (A the total area) needs at least `target` patches, so refine() towards it stops
/// at the round that reaches the target, splitting the largest triangles first within that
/// round. Lands on the target or a few triangles above it (the conforming closure of the last
/// split); only triangles that round left whole exceed the bound (it takes the largest
/// first). Conforming and deterministic like refine(); report->areaBound is A/target.
Mesh refineToCount(const Mesh& scene, int64_t target, MeshingReport* report = nullptr,
                   const ContactEdges* contactEdges = nullptr);

/// Adaptive refinement: splits each triangle of `marked` (most urgent first) by bisecting its
/// longest edge, `levels` times (2: a marked triangle's children are split again, quartering
/// it), each split with its conforming closure (the neighbours across a split edge are split
/// too, so no T-junctions appear). A split triangle's children take its place in the order, so
/// the ids are a pure function of the mesh and the marks, and patches before the first split
/// keep theirs. Splitting stops before a mark whose closure would take the mesh past `budget`
/// triangles (the marks taken in order, each with its closure; the first is always taken).
/// `parentOf` (if not null): per new triangle, the triangle of
/// `mesh` it lies in.
Mesh refineMarked(const Mesh& mesh, const std::vector<int64_t>& marked, int levels, int64_t budget,
                  std::vector<int64_t>* parentOf = nullptr);

/// The patches an adaptive refinement round splits, most urgent first: whole classes of patches
/// of about equal error (within 2^(1/8)), largest first, until they hold `share` of the total
/// (Dörfler's bulk marking), and at least `minMarks` patches (whole classes, of those with an
/// error), at most `maxMarks` of them; by id within a class. `error`: per patch, ≥ 0, as exact
/// integers, so that the marks are a pure function of them.
std::vector<int64_t> markLargestErrors(const std::vector<int64_t>& error, double share,
                                       int64_t maxMarks, int64_t minMarks = 0);

/// A bisection that merging its halves back undoes: `vertex` is exactly the midpoint of the
/// edge `ends` (a, b), and its triangles are the halves of one triangle across that edge, or of
/// the two that shared it: halves[2p] holds a, halves[2p + 1] holds b, both with the same apex,
/// face and material (halves[2], halves[3] are -1 for one triangle).
struct Bisection {
  int64_t vertex = -1;
  std::array<int64_t, 2> ends{};
  std::array<int64_t, 4> halves{-1, -1, -1, -1};
};

/// The bisections of `mesh` that can be undone, by vertex (refinement's midpoints whose stars
/// it has not split further; a vertex cut along a contact or loaded from the scene is none).
std::vector<Bisection> undoableBisections(const Mesh& mesh);

/// Coarsening: `mesh` with the bisections at `vertices` undone, each pair of halves merged
/// into the triangle they came from (the first half's place in the order; the vertex dropped,
/// the others renumbered in order), so the ids are a pure function of the mesh and `vertices`,
/// and the mesh stays conforming. `halvesOf` (if not null): per new triangle, the triangle of
/// `mesh` it is and the second half merged into it (-1: none). Throws Error(kFailure) for a
/// vertex that is no undoable bisection, or two that share a triangle.
Mesh undoBisections(const Mesh& mesh, const std::vector<int64_t>& vertices,
                    std::vector<std::array<int64_t, 2>>* halvesOf = nullptr);

/// The bisections an adaptive round undoes where the light is flat: of `candidates`, those
/// whose halves are all `mergeable`, least error first (the sum of `error` over their halves,
/// per triangle as markLargestErrors takes it; whole classes of about equal error at a time,
/// by vertex within a class), while their errors sum to at most `errorBudget`. Their vertices,
/// ascending.
std::vector<int64_t> markFlatBisections(const std::vector<Bisection>& candidates,
                                        const std::vector<int64_t>& error,
                                        const std::vector<char>& mergeable, double errorBudget);

/// Reorders triangles along a Morton (Z-order) curve of their centroids, so that patches with
/// near ids are near in space; ties keep the input order. Vertices are kept.
Mesh orderAlongCurve(Mesh patches);

/// Each triangle's key on that curve: its centroid's cell of a 2^21 grid over the bounding box's
/// largest extent, the bits of x, y and z interleaved. Patches in curve order have ascending
/// keys, and those sharing a key's first bits lie in one cube of the grid.
std::vector<uint64_t> curveKeys(const Mesh& patches);

/// The patches a rank owns: global ids [begin, end).
struct PatchRange {
  int64_t begin = 0;
  int64_t end = 0;
  int64_t size() const { return end - begin; }
  bool contains(int64_t id) const { return id >= begin && id < end; }
};

/// Contiguous blocks with counts differing by at most one; the first (count % ranks) blocks
/// get the extra patch.
PatchRange blockOf(int64_t count, int rank, int ranks);

/// The rank that owns patch `id` under blockOf().
int ownerOf(int64_t id, int64_t count, int ranks);

/// One contiguous block of patch ids per rank, in rank order (rank r owns [bound r, bound r+1)):
/// the shape the result and checkpoint writers and PETSc's row ownership rely on. Blocks may be
/// empty. Where they are cut does not change the answer, only who computes which rows.
class Blocks {
 public:
  /// Equal counts: the blocks of blockOf().
  static Blocks byCount(int64_t count, int ranks);
  /// Equal cost: `cost[i]` (≥ 0, finite) is patch i's share of the work; each boundary is the
  /// id at which the prefix sum of cost comes nearest to its share r/ranks of the total, so a
  /// block's cost is within the largest single cost of total/ranks. By count when the total is
  /// not positive and finite.
  static Blocks byCost(const std::vector<double>& cost, int ranks);
  /// The same with the cost given per run of patches along the curve: each of the patches
  /// [runStart[s], runStart[s + 1]) costs perPatch[s] (runStart from 0 to the patch count).
  static Blocks byCost(const std::vector<int64_t>& runStart, const std::vector<double>& perPatch,
                       int ranks);
  /// From ranks + 1 nondecreasing boundaries, the first 0 (as byCost() and byCount() make them).
  explicit Blocks(std::vector<int64_t> boundaries);

  int ranks() const { return static_cast<int>(bound_.size()) - 1; }
  int64_t count() const { return bound_.back(); }
  PatchRange of(int rank) const { return {bound_[rank], bound_[rank + 1]}; }
  /// The rank whose block holds `id` (0 ≤ id < count()).
  int owner(int64_t id) const;
  const std::vector<int64_t>& boundaries() const { return bound_; }

 private:
  std::vector<int64_t> bound_;
};

}  // namespace radiosity::partition
