// Private to partition/: faces laid over others, for cutAtContacts() (contact_cuts.cpp). A
// poster on a wall, a lamp panel flush on a ceiling, a room's floor on the ground it stands on:
// coplanar, facing the same way, overlapping. Rays meeting both hit either (the pane vanishes
// from the picture, light lands on the wall under it), so the face laid over covers the one
// below: the covered part is left out, as every lighting tool cuts the opening. Which lies over
// which is read from the flat regions they belong to (coplanar triangles joined along edges,
// facing alike): the smaller region lies over the larger (the poster is smaller than the wall it
// hangs on, the room's floor than the ground); of equal ones, the later in the file (drawn last,
// as a painter would).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace radiosity::partition::contacts {

class FaceCover {
 public:
  /// `overlaps`: pairs of triangles of `mesh` (not owned) that are coplanar, face the same way
  /// and overlap with an area (or are the same triangle twice).
  FaceCover(const Mesh& mesh, const std::vector<std::pair<int64_t, int64_t>>& overlaps);

  bool empty() const { return over_.empty(); }

  /// The triangles lying over triangle t, of those it overlaps: none for most.
  const std::vector<int64_t>& over(int64_t t) const;

  /// The first triangle of over(t) whose inside holds `point` (a point of t's plane), or -1.
  int64_t coveringAt(int64_t t, const Vec3& point) const;

 private:
  const Mesh& mesh_;
  std::vector<std::vector<int64_t>> over_;  // empty when nothing overlaps
};

}  // namespace radiosity::partition::contacts
