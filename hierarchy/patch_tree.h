// The hierarchy hierarchical transport exchanges light over: a binary tree whose every node is a
// contiguous range of patch ids. The patches are numbered along a Morton curve
// (partition::orderAlongCurve), so a node split where its keys' highest differing bit flips is
// a cube of space, and a node's patches are one block of rows: what a node gathers or sends is a
// range of the rank blocks, and the tree is the same on any number of ranks (a function of the
// mesh alone). Each node has what the transport's oracle and its push and pull need: area,
// centroid, bounding radius, the cone of its normals, and whether its patches are of one
// material.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace radiosity::hierarchy {

/// One node of the tree, as the oracle and the transport read it: the patches [begin, end).
struct ClusterNode {
  int64_t begin = 0, end = 0;
  int64_t child[2] = {-1, -1};  ///< node ids; -1 for a leaf (one patch)
  double area = 0;
  Vec3 centroid{};    ///< area-weighted
  double radius = 0;  ///< of a sphere about the centroid holding every corner
  Vec3 normal{};      ///< the area-weighted mean of the unit normals, made unit; 0: they cancel
  double cone = 0;    ///< half-angle (radians) about `normal` holding every patch's normal
  /// Every patch under the node has the same ρ and E (one material): its mean B is then a mean
  /// of light alone, not of surfaces that send differently.
  bool uniform = true;
  bool emits = false;  ///< some patch under the node has E > 0
  /// The input face (Mesh::sourceFace) every patch under the node came from; -1: several.
  int64_t face = -1;

  bool isLeaf() const { return child[0] < 0; }
  int64_t size() const { return end - begin; }
  bool holds(int64_t patch) const { return patch >= begin && patch < end; }
};

/// The tree over every patch of a mesh, which it views (the mesh must outlive it and not
/// change). Node ids: the n − 1 inner nodes first, depth first (the root is 0 and a node's inner
/// children come after it), then the leaves, patch p's being innerCount() + p. The leaves are
/// not stored (their figures are their patch's), and the inner nodes' figures are floats (rounded
/// outwards where they bound): 72 bytes a patch.
class PatchTree {
 public:
  /// Builds the tree over `patches` (numbered along the curve: orderAlongCurve; in any other
  /// order the nodes are split at their middle instead, still a valid tree but not cubes of
  /// space).
  explicit PatchTree(const Mesh& patches);

  int64_t patchCount() const { return patches_->triangleCount(); }
  int64_t innerCount() const { return innerCount_; }
  int64_t nodeCount() const { return innerCount() + patchCount(); }
  int64_t root() const { return 0; }  ///< (with one patch, its leaf)
  int64_t leafOf(int64_t patch) const { return innerCount() + patch; }
  bool isLeaf(int64_t id) const { return id >= innerCount(); }
  ClusterNode node(int64_t id) const;
  double area(int64_t id) const;
  /// One past the last patch under node `id`.
  int64_t end(int64_t id) const {
    return isLeaf(id) ? id - innerCount() + 1 : inner_[static_cast<size_t>(id)].end;
  }
  /// The child of inner node `id` that holds `patch` (which the node must hold).
  int64_t childHolding(int64_t id, int64_t patch) const {
    const Inner& n = inner_[static_cast<size_t>(id)];
    const int64_t first = n.child[0];
    const int64_t firstEnd = isLeaf(first) ? first - innerCount() + 1 : inner_[first].end;
    return patch < firstEnd ? first : n.child[1];
  }
  /// The children of inner node `id`.
  std::array<int64_t, 2> children(int64_t id) const {
    const Inner& n = inner_[static_cast<size_t>(id)];
    return {n.child[0], n.child[1]};
  }
  /// Bytes the tree holds, for the memory reports.
  int64_t bytes() const { return static_cast<int64_t>(inner_.capacity() * sizeof(Inner)); }

 private:
  struct Inner {
    int64_t begin = 0, end = 0;
    int32_t child[2] = {-1, -1};  ///< (node ids below 2^31: up to 10^9 patches)
    double area = 0;
    float centroid[3] = {0, 0, 0};
    float radius = 0;
    float normal[3] = {0, 0, 0};
    float cone = 0;
    bool uniform = true, emits = false;
    int32_t face = -1;  ///< -1: several (or one past 2^31, taken as several)
  };
  void gather(int64_t id);

  const Mesh* patches_;
  int64_t innerCount_ = 0;  ///< n − 1 (0 for one patch or none), from the start of the build
  std::vector<Inner> inner_;
};

}  // namespace radiosity::hierarchy
