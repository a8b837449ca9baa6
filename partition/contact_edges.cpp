// The edges along contact lines (partition::contactEdges): where two triangles meet at a
// concave crease, for refinement to follow them.
#include "partition/contact_finder.h"
#include "partition/partition.h"

namespace radiosity::partition {

ContactEdges contactEdges(const Mesh& mesh) {
  contacts::ContactFinder finder(mesh, contacts::snapTolerance(mesh));
  ContactEdges edges;
  finder.touchingPairs(true, [&](int64_t s, int64_t t) { finder.addConcaveContact(s, t, edges); });
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace radiosity::partition
