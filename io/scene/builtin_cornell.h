// Private to io/scene: builtin:cornell, the Cornell box (builtin_cornell.cpp).
#pragma once

#include "core/mesh.h"
#include "io/scene/scene_builder.h"

namespace radiosity::detail {

/// The Cornell box as measured, in mm times the parameter "scale", its light's exitance times
/// "light".
Mesh cornell(const Params& p);

}  // namespace radiosity::detail
