// Private to io/: the MTL side of the OBJ reader.
#pragma once

#include <map>
#include <set>
#include <string>

#include "io/scene/scene_internal.h"

namespace radiosity::detail {

struct Material {
  Rgb reflectance = kDefaultReflectance;  ///< Kd
  Rgb emission = {0, 0, 0};               ///< Ke
  bool hasKd = false;
  std::string file;  ///< where it was defined, for messages
  long line = 0;
};

/// All materials of the mtllib files an OBJ names; a later definition of a name replaces an
/// earlier one.
struct MaterialLibrary {
  std::map<std::string, Material> materials;
  std::set<std::string> ignoredKeywords;  ///< MTL statements we do not use, for one warning
};

/// Adds the materials of the MTL text `content` (read from `path`) to `library`. Throws
/// InputError naming `path` and the line for bad or out-of-range values.
void readMtl(const std::string& path, std::string content, MaterialLibrary& library);

}  // namespace radiosity::detail
