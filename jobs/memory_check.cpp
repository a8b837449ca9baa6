#include "jobs/memory_check.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "io/io.h"

namespace radiosity::jobs {

void checkMeshFits(MPI_Comm comm, double totalArea, int64_t inputTriangles, int64_t patches,
                   double maxArea, const std::string& option) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int ranksOnNode = 1;
  MPI_Comm_size(node, &ranksOnNode);
  MPI_Comm_free(&node);
  const double memory =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  const double asked = patches > 0 ? static_cast<double>(patches) : totalArea / maxArea;
  const double predicted = std::max(static_cast<double>(inputTriangles), asked);
  const double bytes = predicted * kMeshBytesPerPatch * ranksOnNode;
  if (!(memory > 0) || bytes <= memory) return;
  char text[400];
  std::snprintf(text, sizeof text,
                "%s asks for about %.3g patches: about %.3g GB for the mesh alone on the %d "
                "rank(s) of this node, which has %.3g GB; ask for fewer patches",
                option.c_str(), predicted, bytes / 1e9, ranksOnNode, memory / 1e9);
  throw Error(exit_code::kUsage, text);
}

}  // namespace radiosity::jobs
