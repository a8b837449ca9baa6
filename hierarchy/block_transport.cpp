// The transport across ranks (block_transport.h).
#include "hierarchy/block_transport.h"

#include <algorithm>
#include <array>
#include <map>
#include <type_traits>

namespace radiosity::hierarchy {

static_assert(std::is_same_v<PetscReal, double>, "the node means are moved as doubles");

namespace {

// The inner nodes wholly inside [begin, end) (not leaves), as runs of ids: a subtree's inner
// nodes are consecutive ids (depth-first numbering), so a run is a maximal subtree's.
struct Run {
  int64_t first = 0, count = 0, offset = 0;  ///< ids [first, first + count) at local offset
};

std::vector<Run> insideRuns(const PatchTree& tree, partition::PatchRange block, int64_t offset) {
  std::vector<Run> runs;
  if (block.size() == 0 || tree.innerCount() == 0) return runs;
  std::vector<int64_t> open{tree.root()};
  while (!open.empty()) {  // depth first, the first child first: the runs come in id order
    const int64_t id = open.back();
    open.pop_back();
    if (tree.isLeaf(id)) continue;
    const ClusterNode node = tree.node(id);
    if (node.end <= block.begin || node.begin >= block.end) continue;
    if (node.begin >= block.begin && node.end <= block.end) {
      runs.push_back({id, node.size() - 1, offset});
      offset += node.size() - 1;
      continue;
    }
    open.push_back(node.child[1]);
    open.push_back(node.child[0]);
  }
  return runs;
}

// Inner nodes holding both sides of some boundary between two blocks, in id order.
std::vector<int64_t> straddlingNodes(const PatchTree& tree,
                                     const std::vector<partition::PatchRange>& blocks) {
  std::vector<int64_t> ids;
  for (const partition::PatchRange& block : blocks) {
    const int64_t q = block.begin;  // the boundary before the block
    if (q <= 0 || q >= tree.patchCount()) continue;
    int64_t id = tree.root();
    while (!tree.isLeaf(id)) {
      const ClusterNode node = tree.node(id);
      if (!(node.begin < q && q < node.end)) break;
      ids.push_back(id);
      id = tree.childHolding(id, q - 1);
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// Where `id` lies among sorted ids: its position, or −1.
int64_t positionIn(const std::vector<int64_t>& ids, int64_t id) {
  const auto at = std::lower_bound(ids.begin(), ids.end(), id);
  return at != ids.end() && *at == id ? at - ids.begin() : -1;
}

// Index of inner id among the runs' local indices, or −1.
int64_t inRuns(const std::vector<Run>& runs, int64_t id) {
  auto at = std::upper_bound(runs.begin(), runs.end(), id,
                             [](int64_t v, const Run& run) { return v < run.first; });
  if (at == runs.begin()) return -1;
  --at;
  return id < at->first + at->count ? at->offset + (id - at->first) : -1;
}

}  // namespace

// The rank's nodes, by local index: its leaves [0, L), the inner nodes inside its block
// [L, L + I), the straddling nodes [L + I, L + I + S), then the ghost sources.
struct BlockTransport::Local {
  int64_t leaves = 0, inside = 0;
  std::vector<Run> runs;
  std::vector<int64_t> straddling;  ///< ids, the same on every rank
  /// The children of straddling nodes that straddle nothing, ids in order, and the local index
  /// of each (−1: not in this block); their means are shared.
  std::vector<int64_t> boundary;
  std::vector<int64_t> boundaryLocal;
  /// Per straddling node, its children: as a straddling node (≥ 0) or as ~(boundary position).
  std::vector<std::array<int64_t, 2>> straddlingChild;
  std::vector<int64_t> ghosts;  ///< ids of the sources fetched from other blocks
  /// Each local node's figures for linear push, and each kept inner node's childrenCentre (by
  /// local index; empty for uniform push).
  std::vector<NodeShape> shape;
  std::vector<Vec3> centre;

  void layOut(const PatchTree& tree, partition::PatchRange owned,
              const std::vector<partition::PatchRange>& blocks);
  void cacheShapes(const PatchTree& tree, partition::PatchRange owned);

  int64_t firstStraddling() const { return leaves + inside; }
  int64_t firstGhost() const { return leaves + inside + static_cast<int64_t>(straddling.size()); }
  int64_t count() const { return firstGhost() + static_cast<int64_t>(ghosts.size()); }

  /// The local index of node `id` among the kept ones (leaves, inside, straddling), or −1.
  int64_t kept(const PatchTree& tree, partition::PatchRange owned, int64_t id) const {
    if (tree.isLeaf(id)) {
      const int64_t p = id - tree.innerCount();
      return owned.contains(p) ? p - owned.begin : -1;
    }
    const int64_t inner = inRuns(runs, id);
    if (inner >= 0) return inner;
    const int64_t s = positionIn(straddling, id);
    return s >= 0 ? firstStraddling() + s : -1;
  }
};

BlockTransport::BlockTransport(MPI_Comm comm, const PatchTree& tree, partition::PatchRange owned,
                               Push push)
    : comm_(comm), tree_(tree), owned_(owned), push_(push), local_(std::make_unique<Local>()) {}

BlockTransport::~BlockTransport() { PetscSFDestroy(&ghosts_); }

PetscErrorCode BlockTransport::create(MPI_Comm comm, const PatchTree& tree,
                                      partition::PatchRange owned, const Links& links, Push push,
                                      std::unique_ptr<BlockTransport>* transport) {
  return build(
      comm, tree, owned, [&](const LinkVisitor& visit) { links.forEach(visit); }, push, transport);
}

PetscErrorCode BlockTransport::create(MPI_Comm comm, const PatchTree& tree,
                                      partition::PatchRange owned, const LinkTally& links,
                                      Push push, std::unique_ptr<BlockTransport>* transport) {
  return build(
      comm, tree, owned, [&](const LinkVisitor& visit) { links.forEach(visit); }, push, transport);
}

// Which nodes the rank keeps: its own, and the straddling ones with their children.
void BlockTransport::Local::layOut(const PatchTree& tree, partition::PatchRange owned,
                                   const std::vector<partition::PatchRange>& blocks) {
  leaves = owned.size();
  runs = insideRuns(tree, owned, leaves);
  for (const Run& run : runs) inside += run.count;
  straddling = straddlingNodes(tree, blocks);
  for (int64_t id : straddling)
    for (int64_t child : tree.children(id))
      if (positionIn(straddling, child) < 0) boundary.push_back(child);
  std::sort(boundary.begin(), boundary.end());
  for (int64_t id : boundary) boundaryLocal.push_back(kept(tree, owned, id));
  for (int64_t id : straddling) {
    std::array<int64_t, 2> child{};
    for (int c = 0; c < 2; ++c) {
      const int64_t childId = tree.children(id)[c];
      const int64_t s = positionIn(straddling, childId);
      child[c] = s >= 0 ? s : ~positionIn(boundary, childId);
    }
    straddlingChild.push_back(child);
  }
}

// The figures linear push reads: every local node's shape and each kept inner node's centre.
void BlockTransport::Local::cacheShapes(const PatchTree& tree, partition::PatchRange owned) {
  shape.resize(static_cast<size_t>(count()));
  for (int64_t p = 0; p < leaves; ++p) shape[p] = shapeOf(tree.node(tree.leafOf(owned.begin + p)));
  for (const Run& run : runs)
    for (int64_t k = 0; k < run.count; ++k)
      shape[run.offset + k] = shapeOf(tree.node(run.first + k));
  for (size_t s = 0; s < straddling.size(); ++s)
    shape[firstStraddling() + s] = shapeOf(tree.node(straddling[s]));
  for (size_t g = 0; g < ghosts.size(); ++g)
    shape[firstGhost() + g] = shapeOf(tree.node(ghosts[g]));
  centre.resize(static_cast<size_t>(firstGhost()));
  for (const Run& run : runs)
    for (int64_t k = 0; k < run.count; ++k)
      centre[run.offset + k] = childrenCentre(tree, run.first + k);
  for (size_t s = 0; s < straddling.size(); ++s)
    centre[firstStraddling() + s] = childrenCentre(tree, straddling[s]);
}

PetscErrorCode BlockTransport::build(MPI_Comm comm, const PatchTree& tree,
                                     partition::PatchRange owned,
                                     const std::function<void(const LinkVisitor&)>& eachLink,
                                     Push push, std::unique_ptr<BlockTransport>* transport) {
  PetscFunctionBeginUser;
  std::unique_ptr<BlockTransport> t(new BlockTransport(comm, tree, owned, push));
  int ranks = 1;
  PetscCallMPI(MPI_Comm_size(comm, &ranks));
  std::vector<int64_t> ends(static_cast<size_t>(ranks) * 2);
  const int64_t mine[2] = {owned.begin, owned.end};
  PetscCallMPI(MPI_Allgather(mine, 2, MPI_INT64_T, ends.data(), 2, MPI_INT64_T, comm));
  std::vector<partition::PatchRange> blocks(static_cast<size_t>(ranks));
  for (int k = 0; k < ranks; ++k) {
    blocks[k] = {ends[2 * k], ends[2 * k + 1]};
    PetscCheck(blocks[k].begin == (k == 0 ? 0 : blocks[k - 1].end) && blocks[k].size() >= 0 &&
                   (k + 1 < ranks || blocks[k].end == tree.patchCount()),
               comm, PETSC_ERR_ARG_INCOMP,
               "the ranks' blocks do not tile the patches in rank order (rank %d: %lld..%lld)", k,
               static_cast<long long>(blocks[k].begin), static_cast<long long>(blocks[k].end));
  }
  t->local_->layOut(tree, owned, blocks);
  PetscCall(t->placeLinks(eachLink));
  PetscCall(t->connectGhosts(blocks));
  if (push == Push::kLinear) t->local_->cacheShapes(tree, owned);
  *transport = std::move(t);
  PetscFunctionReturn(0);
}

// The links by receiver's local index (counted, then placed: no copy of them), the sources kept
// here or fetched (ghosts).
PetscErrorCode BlockTransport::placeLinks(const std::function<void(const LinkVisitor&)>& eachLink) {
  PetscFunctionBeginUser;
  Local& local = *local_;
  receiverStart_.assign(static_cast<size_t>(local.firstGhost()) + 1, 0);
  bool foreign = false;
  eachLink([&](int64_t receiver, int64_t source, double) {
    const int64_t r = local.kept(tree_, owned_, receiver);
    if (r < 0) {
      foreign = true;
      return;
    }
    ++receiverStart_[r + 1];
    if (local.kept(tree_, owned_, source) < 0) local.ghosts.push_back(source);
  });
  PetscCheck(!foreign, comm_, PETSC_ERR_ARG_WRONG,
             "a link's receiver holds none of this rank's patches");
  std::sort(local.ghosts.begin(), local.ghosts.end());
  local.ghosts.erase(std::unique(local.ghosts.begin(), local.ghosts.end()), local.ghosts.end());
  local.ghosts.shrink_to_fit();
  PetscCheck(local.count() < INT32_MAX, comm_, PETSC_ERR_SUP,
             "a rank keeps %lld nodes, too many for the transport's 32-bit indices",
             static_cast<long long>(local.count()));
  for (size_t r = 1; r < receiverStart_.size(); ++r) receiverStart_[r] += receiverStart_[r - 1];
  source_.resize(static_cast<size_t>(receiverStart_.back()));
  factor_.resize(source_.size());
  std::vector<int64_t> next(receiverStart_.begin(), receiverStart_.end() - 1);
  eachLink([&](int64_t receiver, int64_t source, double factor) {
    const int64_t at = next[local.kept(tree_, owned_, receiver)]++;
    int64_t s = local.kept(tree_, owned_, source);
    if (s < 0) s = local.firstGhost() + positionIn(local.ghosts, source);
    source_[at] = static_cast<int32_t>(s);
    factor_[at] = factor;
  });
  PetscFunctionReturn(0);
}

// Each ghost from the rank whose block holds it, at that rank's local index.
PetscErrorCode BlockTransport::connectGhosts(const std::vector<partition::PatchRange>& blocks) {
  PetscFunctionBeginUser;
  const Local& local = *local_;
  std::vector<PetscSFNode> remote(local.ghosts.size());
  std::map<int, std::vector<Run>> runsOf;
  for (size_t g = 0; g < local.ghosts.size(); ++g) {
    const int64_t id = local.ghosts[g];
    const int64_t first = tree_.node(id).begin;
    int owner = 0;
    while (!blocks[owner].contains(first)) ++owner;
    int64_t index = first - blocks[owner].begin;
    if (!tree_.isLeaf(id)) {
      auto found = runsOf.find(owner);
      if (found == runsOf.end())
        found = runsOf.emplace(owner, insideRuns(tree_, blocks[owner], blocks[owner].size())).first;
      index = inRuns(found->second, id);
    }
    PetscCheck(index >= 0, comm_, PETSC_ERR_PLIB, "a ghost node is not inside its owner's block");
    remote[g].rank = owner;
    remote[g].index = static_cast<PetscInt>(index);
  }
  PetscCall(PetscSFCreate(comm_, &ghosts_));
  PetscCall(PetscSFSetGraph(ghosts_, static_cast<PetscInt>(local.leaves + local.inside),
                            static_cast<PetscInt>(local.ghosts.size()), nullptr, PETSC_COPY_VALUES,
                            remote.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(ghosts_));
  PetscFunctionReturn(0);
}

int64_t BlockTransport::bytes() const {
  const int64_t links = linkCount() * static_cast<int64_t>(sizeof(int32_t) + sizeof(double));
  const int64_t perNode = static_cast<int64_t>(
      (receiverStart_.capacity() + mean_.capacity() + gathered_.capacity()) * sizeof(double) +
      (slope_.capacity() + local_->centre.capacity()) * sizeof(Vec3) +
      local_->shape.capacity() * sizeof(NodeShape));
  return links + perNode;
}

PetscErrorCode BlockTransport::apply(const double* x, double* y, int components) {
  PetscFunctionBeginUser;
  PetscCheck(components >= 1, comm_, PETSC_ERR_ARG_OUTOFRANGE, "no components to transport");
  const auto k = static_cast<size_t>(components);
  const Local& local = *local_;
  mean_.resize(static_cast<size_t>(local.count()) * k);
  gathered_.resize(static_cast<size_t>(local.firstGhost()) * k);
  if (push_ == Push::kLinear) slope_.resize(gathered_.size());
  PetscCall(pull(x, components));
  gather(components);
  PetscCall(pushDown(y, components));
  PetscFunctionReturn(0);
}

// The means, bottom up as the serial pull takes them: the rank's own nodes, then the straddling
// nodes from their children's shared means, then the ghosts from their owners. Component c of
// local node v is at v · k + c.
PetscErrorCode BlockTransport::pull(const double* x, int components) {
  PetscFunctionBeginUser;
  const Local& local = *local_;
  const int64_t k = components;
  std::copy(x, x + local.leaves * k, mean_.begin());
  // (the serial pull's formula, operation for operation)
  const auto meanOf = [&](int64_t id, int64_t childA, const double* a, int64_t childB,
                          const double* b, double* to) {
    const double area = tree_.area(id), areaA = tree_.area(childA), areaB = tree_.area(childB);
    for (int64_t c = 0; c < k; ++c) to[c] = area > 0 ? (areaA * a[c] + areaB * b[c]) / area : 0.0;
  };
  for (auto run = local.runs.rbegin(); run != local.runs.rend(); ++run)
    for (int64_t i = run->count - 1; i >= 0; --i) {
      const int64_t id = run->first + i;
      const auto [a, b] = tree_.children(id);
      const auto at = [&](int64_t child) {
        return &mean_[(tree_.isLeaf(child) ? child - tree_.leafOf(owned_.begin)
                                           : run->offset + (child - run->first)) *
                      k];
      };
      meanOf(id, a, at(a), b, at(b), &mean_[(run->offset + i) * k]);
    }
  const auto boundary = static_cast<int64_t>(local.boundary.size());
  shared_.assign(static_cast<size_t>(boundary * k), 0.0);
  for (int64_t i = 0; i < boundary; ++i)
    if (local.boundaryLocal[i] >= 0)
      std::copy_n(&mean_[local.boundaryLocal[i] * k], k, &shared_[i * k]);
  if (boundary > 0)
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, shared_.data(), static_cast<int>(shared_.size()),
                               MPI_DOUBLE, MPI_SUM, comm_));
  for (int64_t s = static_cast<int64_t>(local.straddling.size()) - 1; s >= 0; --s) {
    const int64_t id = local.straddling[s];
    const auto [a, b] = tree_.children(id);
    const auto meanAt = [&](int64_t child) {
      return child >= 0 ? &mean_[(local.firstStraddling() + child) * k] : &shared_[~child * k];
    };
    meanOf(id, a, meanAt(local.straddlingChild[s][0]), b, meanAt(local.straddlingChild[s][1]),
           &mean_[(local.firstStraddling() + s) * k]);
  }
  MPI_Datatype unit;
  PetscCallMPI(MPI_Type_contiguous(components, MPI_DOUBLE, &unit));
  PetscCallMPI(MPI_Type_commit(&unit));
  double* ghosts = mean_.data() + local.firstGhost() * k;
  const PetscErrorCode begun = PetscSFBcastBegin(ghosts_, unit, mean_.data(), ghosts, MPI_REPLACE);
  const PetscErrorCode ended =
      begun ? begun : PetscSFBcastEnd(ghosts_, unit, mean_.data(), ghosts, MPI_REPLACE);
  PetscCallMPI(MPI_Type_free(&unit));
  PetscCall(ended);
  PetscFunctionReturn(0);
}

// Each kept receiver's light over its links (and, for linear push, its slope): the kernel's
// gradient once a link for every component.
void BlockTransport::gather(int components) {
  const Local& local = *local_;
  const int64_t k = components;
  const bool linear = push_ == Push::kLinear;
  std::fill(gathered_.begin(), gathered_.end(), 0.0);
  if (linear) std::fill(slope_.begin(), slope_.end(), Vec3{});
  for (int64_t r = 0; r < local.firstGhost(); ++r) {
    double* light = &gathered_[r * k];
    const bool sloped = linear && r >= local.leaves;
    for (int64_t l = receiverStart_[r]; l < receiverStart_[r + 1]; ++l) {
      const double* mean = &mean_[source_[l] * k];
      for (int64_t c = 0; c < k; ++c) light[c] += factor_[l] * mean[c];
      if (!sloped) continue;
      const Vec3 g = kernelGradient(local.shape[r], local.shape[source_[l]]);
      for (int64_t c = 0; c < k; ++c)
        slope_[r * k + c] = slope_[r * k + c] + (factor_[l] * mean[c]) * g;
    }
  }
}

// The straddling receivers' partial sums added up, then every kept node's light handed down to
// its children, parents first, and the leaves' read out.
PetscErrorCode BlockTransport::pushDown(double* y, int components) {
  PetscFunctionBeginUser;
  const Local& local = *local_;
  const int64_t k = components;
  const bool linear = push_ == Push::kLinear;
  const auto straddling = static_cast<int64_t>(local.straddling.size());
  const int64_t first = local.firstStraddling();
  if (straddling > 0) {
    const int64_t width = linear ? 4 : 1;  // the light and, for linear push, its slope
    shared_.assign(static_cast<size_t>(straddling * k * width), 0.0);
    for (int64_t v = 0; v < straddling * k; ++v) {
      shared_[v * width] = gathered_[first * k + v];
      for (int64_t c = 1; c < width; ++c) shared_[v * width + c] = slope_[first * k + v][c - 1];
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, shared_.data(), static_cast<int>(shared_.size()),
                               MPI_DOUBLE, MPI_SUM, comm_));
    for (int64_t v = 0; v < straddling * k; ++v) {
      gathered_[first * k + v] = shared_[v * width];
      for (int64_t c = 1; c < width; ++c) slope_[first * k + v][c - 1] = shared_[v * width + c];
    }
  }
  const auto hand = [&](int64_t from, int64_t to, bool toInner) {
    for (int64_t c = 0; c < k; ++c) {
      gathered_[to * k + c] += gathered_[from * k + c];
      if (!linear) continue;
      gathered_[to * k + c] +=
          dot(slope_[from * k + c], local.shape[to].centroid - local.centre[from]);
      if (toInner) slope_[to * k + c] = slope_[to * k + c] + slope_[from * k + c];
    }
  };
  for (int64_t s = 0; s < straddling; ++s)
    for (int64_t child : tree_.children(local.straddling[s])) {
      const int64_t to = local.kept(tree_, owned_, child);
      if (to >= 0) hand(first + s, to, !tree_.isLeaf(child));
    }
  for (const Run& run : local.runs)
    for (int64_t i = 0; i < run.count; ++i) {
      const int64_t id = run.first + i;
      for (int64_t child : tree_.children(id)) {
        const bool leaf = tree_.isLeaf(child);
        hand(run.offset + i,
             leaf ? child - tree_.leafOf(owned_.begin) : run.offset + (child - run.first), !leaf);
      }
    }
  std::copy(gathered_.begin(), gathered_.begin() + local.leaves * k, y);
  PetscFunctionReturn(0);
}

}  // namespace radiosity::hierarchy
