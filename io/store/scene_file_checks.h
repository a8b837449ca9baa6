// Private to io/store: the checks of an HDF5 scene file's rows that the reader makes on each
// rank's slab as it reads them (scene_file_reader.cpp); each throws the InputError naming the
// file, the dataset, the row and the problem.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::scene_file_checks {

/// "dataset NAME: row ROW", how a message names a row.
std::string rowOf(const char* name, int64_t row);

/// Rows [first, first + count) of /mesh/vertices: finite, within kMaxCoordinate.
void checkVertices(const std::string& path, int64_t first, int64_t count, const Vec3* v);

/// Rows [first, first + count) of /mesh/triangles: corners among the `nv` vertices.
void checkTriangles(const std::string& path, int64_t first, int64_t count, const Triangle* t,
                    int64_t nv);

/// Rows [first, first + count) of the index dataset `name`: rows of `of`, which has `end`.
void checkIndices(const std::string& path, const char* name, int64_t first, int64_t count,
                  const int32_t* values, int64_t end, const char* of);

/// The materials: ρ within [0, 1], E finite, ≥ 0 and at most kMaxEmission.
void checkMaterials(const std::string& path, const std::vector<Rgb>& reflectance,
                    const std::vector<Rgb>& emission);

}  // namespace radiosity::scene_file_checks
