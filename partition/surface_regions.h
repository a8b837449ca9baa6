// Private to partition/: regions of a mesh, triangles joined along the edges they share (by
// position) where a rule says they belong together, and each region's area: flat regions for
// faces laid over others (face_cover.cpp), smooth surfaces for the least patches a surface gets
// (refine.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"

namespace radiosity::partition {

/// Per triangle, the area of its region: the triangles reached from it across shared edges
/// (vertices compared by position) for which `joined(s, t)` holds, never across one of
/// `apart` (edges as vertex index pairs, compared by position). `regions`, if given, gets how
/// many regions there are.
std::vector<double> regionAreas(const Mesh& mesh,
                                const std::function<bool(int64_t s, int64_t t)>& joined,
                                int64_t* regions = nullptr,
                                const std::vector<std::array<int64_t, 2>>* apart = nullptr);

/// Per triangle, the area of its smooth surface: neighbours whose normals differ by less than
/// 30° (a sphere's facets, a flat wall's triangles; not a wall and the floor it meets), not
/// across a contact line (`contactEdges`: a room's floor and the ground around it, which its
/// walls stand between, are two surfaces).
std::vector<double> smoothSurfaceAreas(
    const Mesh& mesh, int64_t* surfaces = nullptr,
    const std::vector<std::array<int64_t, 2>>* contactEdges = nullptr);

}  // namespace radiosity::partition
