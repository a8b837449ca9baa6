// Whether a reference result (study --reference) is of the study's own mesh: the same patches,
// at the same places, with the same materials. Equal vertex indices alone say little: another
// scene with as many triangles numbers its patches alike, and its B compared patch by patch
// gives a plausible but meaningless error.
#pragma once

#include <string>

#include "core/mesh.h"

namespace radiosity::jobs {

/// What first differs between the reference's mesh and the study's patches, as a phrase ("patch
/// 12's corner 2 is at (0, 1, 0), the study's at (0, 1.5, 0)"), or "" when they match: the
/// triangle and vertex counts and indices exactly; vertex positions within 1e-9 of the mesh's
/// extent; reflectance and emission within 1e-9 relative.
std::string meshDifference(const Mesh& reference, const Mesh& study);

}  // namespace radiosity::jobs
