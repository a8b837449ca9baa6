// partition: turns the scene's triangles into patches (conforming refinement to an area bound),
// gives each patch its global id (ordered along a space-filling curve) and splits the ids into
// one contiguous block per rank. Pure functions of the scene and the options: the same on
// every rank and for any number of ranks.
#pragma once

#include <cstdint>
#include <vector>

#include "io/core/mesh.h"

namespace radiosity::partition {

struct MeshingReport {
  int64_t inputTriangles = 0;
  int64_t patches = 0;
  int refinementRounds = 0;
  double areaBound = 0;  ///< the bound refined to; 0 when none
  double maxPatchArea = 0;
  double worstAspectRatio = 0;  ///< √3·(longest edge)² / (4·area): 1 for equilateral
};

/// Splits longest edges until every triangle has area ≤ maxArea (no refinement when
/// maxArea ≤ 0). Conforming: an edge split in one triangle is split in every triangle sharing
/// it, so no T-junctions appear. Triangles keep their sourceFace and material.
Mesh refine(const Mesh& scene, double maxArea, MeshingReport* report = nullptr);

/// Refines to about `target` patches (none when the scene has that many already): the bound
/// A / target (A the total area) needs at least `target` patches, so refine() towards it stops
/// at the round that reaches the target, splitting the largest triangles first within that
/// round. Lands on the target or a few triangles above it (the conforming closure of the last
/// split); only triangles that round left whole exceed the bound (it takes the largest
/// first). Conforming and deterministic like refine(); report->areaBound is A/target.
Mesh refineToCount(const Mesh& scene, int64_t target, MeshingReport* report = nullptr);

/// Reorders triangles along a Morton (Z-order) curve of their centroids, so that patches with
/// near ids are near in space; ties keep the input order. Vertices are kept.
Mesh orderAlongCurve(Mesh patches);

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
