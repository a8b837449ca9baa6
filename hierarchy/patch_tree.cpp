// The tree over the patches (patch_tree.h): split top-down along the curve keys, its figures
// gathered bottom-up.
#include "hierarchy/patch_tree.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "partition/partition.h"

namespace radiosity::hierarchy {

namespace {

// Where [begin, end) splits: at the first patch whose key has the range's highest differing bit
// set (the two halves are then the two halves of the smallest cube holding it); in the middle
// where the keys are all alike or not in order.
int64_t splitPoint(const std::vector<uint64_t>& keys, bool ordered, int64_t begin, int64_t end) {
  const uint64_t first = keys[begin], last = keys[end - 1];
  if (!ordered || first == last) return begin + (end - begin) / 2;
  const uint64_t bit = uint64_t{1} << (63 - std::countl_zero(first ^ last));
  const uint64_t prefix = (last & ~(bit - 1));  // the upper half's keys are at least this
  return std::lower_bound(keys.begin() + begin, keys.begin() + end, prefix) - keys.begin();
}

// The angle between two unit vectors, accurate near 0 (where acos of the dot loses half the
// digits).
double angleBetween(Vec3 a, Vec3 b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// A bound as a float no smaller than it.
float upwards(double value) {
  const auto f = static_cast<float>(value);
  return f >= value ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

Vec3 toVec3(const float (&v)[3]) { return Vec3{v[0], v[1], v[2]}; }
void store(float (&to)[3], Vec3 v) {
  for (int k = 0; k < 3; ++k) to[k] = static_cast<float>(v[k]);
}

}  // namespace

ClusterNode PatchTree::node(int64_t id) const {
  ClusterNode node;
  if (isLeaf(id)) {
    const Mesh& mesh = *patches_;
    const int64_t t = id - innerCount();
    node.begin = t;
    node.end = t + 1;
    node.area = mesh.area(t);
    node.centroid = mesh.centroid(t);
    for (int k = 0; k < 3; ++k)
      node.radius = std::max(node.radius, length(mesh.corner(t, k) - node.centroid));
    node.normal = mesh.normal(t);
    const Rgb& e = mesh.emission[t];
    node.emits = e[0] > 0 || e[1] > 0 || e[2] > 0;
    node.face = mesh.sourceFace.empty() ? -1 : mesh.sourceFace[t];
    return node;
  }
  const Inner& n = inner_[static_cast<size_t>(id)];
  node.begin = n.begin;
  node.end = n.end;
  node.child[0] = n.child[0];
  node.child[1] = n.child[1];
  node.area = n.area;
  node.centroid = toVec3(n.centroid);
  node.radius = n.radius;
  node.normal = toVec3(n.normal);
  node.cone = n.cone;
  node.uniform = n.uniform;
  node.emits = n.emits;
  node.face = n.face;
  return node;
}

double PatchTree::area(int64_t id) const {
  return isLeaf(id) ? patches_->area(id - innerCount()) : inner_[static_cast<size_t>(id)].area;
}

// An inner node's figures from its two children's. The float centroid moves the sphere's centre
// by rounding: the radius is taken about the stored centroid, and rounded up.
void PatchTree::gather(int64_t id) {
  Inner& n = inner_[static_cast<size_t>(id)];
  const ClusterNode a = node(n.child[0]), b = node(n.child[1]);
  n.area = a.area + b.area;
  const double wa = n.area > 0 ? a.area / n.area : 0.5, wb = 1 - wa;
  store(n.centroid, wa * a.centroid + wb * b.centroid);
  const Vec3 centre = toVec3(n.centroid);
  n.radius = upwards(
      std::max(a.radius + length(a.centroid - centre), b.radius + length(b.centroid - centre)));
  const Vec3 mean = wa * a.normal + wb * b.normal;
  const double meanLength = length(mean);
  if (meanLength < 1e-6) {
    store(n.normal, Vec3{});
    n.cone = static_cast<float>(std::numbers::pi);
  } else {
    store(n.normal, (1.0 / meanLength) * mean);
    const Vec3 axis = toVec3(n.normal);  // (the float axis the cone is about)
    const double axisLength = length(axis);
    n.cone = upwards(std::min(
        std::numbers::pi, std::max(angleBetween((1.0 / axisLength) * axis, a.normal) + a.cone,
                                   angleBetween((1.0 / axisLength) * axis, b.normal) + b.cone)));
  }
  const Mesh& mesh = *patches_;
  const auto sameMaterial = [&](int64_t p, int64_t q) {
    return mesh.reflectance[p] == mesh.reflectance[q] && mesh.emission[p] == mesh.emission[q];
  };
  n.uniform = a.uniform && b.uniform && sameMaterial(a.begin, b.begin);
  n.emits = a.emits || b.emits;
  const bool oneFace = a.face >= 0 && a.face == b.face && a.face <= INT32_MAX;
  n.face = oneFace ? static_cast<int32_t>(a.face) : -1;
}

PatchTree::PatchTree(const Mesh& patches) : patches_(&patches) {
  const int64_t n = patches.triangleCount();
  if (n >= (int64_t{1} << 30)) throw std::length_error("PatchTree: more than 2^30 patches");
  if (n <= 1) return;
  innerCount_ = n - 1;
  const std::vector<uint64_t> keys = partition::curveKeys(patches);
  const bool ordered = std::is_sorted(keys.begin(), keys.end());
  inner_.reserve(static_cast<size_t>(n - 1));
  // Depth first, the first child before the second; a child of one patch is a leaf id. The
  // stack holds the inner nodes whose second child is still to be made, then gathered.
  const auto makeChild = [&](int64_t begin, int64_t end) -> int64_t {
    if (end - begin == 1) return (n - 1) + begin;
    inner_.push_back(Inner{.begin = begin, .end = end});
    return static_cast<int64_t>(inner_.size()) - 1;
  };
  inner_.push_back(Inner{.begin = 0, .end = n});
  struct Open {
    int64_t id;
    int stage;  ///< 0: make the first child; 1: the second; 2: gather
  };
  std::vector<Open> open{{0, 0}};
  while (!open.empty()) {
    Open& top = open.back();
    const int64_t id = top.id;
    if (top.stage == 2) {
      gather(id);
      open.pop_back();
      continue;
    }
    Inner& node = inner_[static_cast<size_t>(id)];
    const int64_t middle = top.stage == 0 ? splitPoint(keys, ordered, node.begin, node.end)
                                          : 0;  // (the second child's begin is the first's end)
    int64_t child;
    if (top.stage == 0) {
      const int64_t begin = node.begin;
      child = makeChild(begin, middle);
      inner_[static_cast<size_t>(id)].child[0] = static_cast<int32_t>(child);
    } else {
      const int64_t first = node.child[0];
      const int64_t begin = first >= n - 1 ? first - (n - 1) + 1 : inner_[first].end;
      const int64_t end = node.end;
      child = makeChild(begin, end);
      inner_[static_cast<size_t>(id)].child[1] = static_cast<int32_t>(child);
    }
    ++top.stage;
    if (child < n - 1) open.push_back({child, 0});
  }
}

}  // namespace radiosity::hierarchy
