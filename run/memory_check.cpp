#include "run/memory_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "run/node_memory.h"

namespace radiosity::run {

namespace {

struct Node {
  int ranks = 1;      ///< ranks of `comm` on this node
  double memory = 0;  ///< bytes of physical memory (0 if unknown)
};

Node thisNode(MPI_Comm comm) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  Node out;
  MPI_Comm_size(node, &out.ranks);
  MPI_Comm_free(&node);
  out.memory = nodeMemoryBytes();
  return out;
}

}  // namespace

void checkFormFactorsFit(MPI_Comm comm, int64_t patches, int64_t columnsPerRow,
                         double bytesPerNonzero, const std::string& rays) {
  const Node node = thisNode(comm);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const double n = static_cast<double>(patches);
  const double perRow = std::min(n, static_cast<double>(columnsPerRow));
  const double nonzeros = n * perRow * node.ranks / ranks;  // this node's share of the rows
  const double bytes = nonzeros * bytesPerNonzero + n * kMeshBytesPerPatch * node.ranks;
  if (!(node.memory > 0) || bytes <= node.memory) return;
  char text[500];
  std::snprintf(
      text, sizeof text,
      "%s on %.3g patches: F may hold up to %.3g nonzeros on this node's %d rank(s) "
      "(%.3g per row), about %.3g GB with the mesh, and the node gives the job %.3g GB; use "
      "fewer rays (--rays) or patches (--max-area, --patches), or spread the ranks "
      "over more nodes",
      rays.c_str(), n, nonzeros, node.ranks, perRow, bytes / 1e9, node.memory / 1e9);
  throw Error(exit_code::kUsage, text);
}

double jobMemoryBytes(MPI_Comm comm) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int nodeRank = 0;
  MPI_Comm_rank(node, &nodeRank);
  MPI_Comm_free(&node);
  // Each node's memory counted once, by its first rank.
  double memory = nodeRank == 0 ? nodeMemoryBytes() : 0.0;
  MPI_Allreduce(MPI_IN_PLACE, &memory, 1, MPI_DOUBLE, MPI_SUM, comm);
  return memory;
}

int64_t patchesThatFit(MPI_Comm comm, int64_t columnsPerRow, double bytesPerNonzero) {
  const double memory = jobMemoryBytes(comm);
  const double perRow = static_cast<double>(std::max<int64_t>(1, columnsPerRow));
  const double rowBytes = perRow * bytesPerNonzero + kMeshBytesPerPatch;
  // Rows shorter than columnsPerRow (fewer patches than rays) only make room for more.
  return std::max<int64_t>(1, static_cast<int64_t>(0.5 * memory / rowBytes));
}

void checkMeshFits(MPI_Comm comm, double totalArea, int64_t inputTriangles, int64_t patches,
                   double maxArea, const std::string& option) {
  const Node node = thisNode(comm);
  const int ranksOnNode = node.ranks;
  const double memory = node.memory;
  const double asked = patches > 0 ? static_cast<double>(patches) : totalArea / maxArea;
  const double predicted = std::max(static_cast<double>(inputTriangles), asked);
  const double bytes = predicted * kMeshBytesPerPatch * ranksOnNode;
  if (!(memory > 0) || bytes <= memory) return;
  char text[400];
  std::snprintf(text, sizeof text,
                "%s asks for about %.3g patches: about %.3g GB for the mesh alone on the %d "
                "rank(s) of this node, which gives the job %.3g GB; ask for fewer patches",
                option.c_str(), predicted, bytes / 1e9, ranksOnNode, memory / 1e9);
  throw Error(exit_code::kUsage, text);
}

}  // namespace radiosity::run
