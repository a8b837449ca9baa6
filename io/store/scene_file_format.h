// Private to io/store: the layout of the HDF5 scene file (docs/scene-format.md), shared by its
// writer and reader.
//
//   root attributes  kind = "radiosity scene", format_version (int32), length_unit (where known),
//                    source, software_<name>
//   /mesh/vertices         float64 [nv, 3]
//   /mesh/triangles        int64   [nt, 3]  0-based rows of /mesh/vertices, counter-clockwise
//                                           seen from the lit side
//   /mesh/material         int32   [nt]     row of /materials of each triangle
//   /mesh/source_face      int64   [nt]     0-based face of the original scene file
//   /materials/reflectance float64 [nm, 3]  ρ per channel, in [0, 1]
//   /materials/emission    float64 [nm, 3]  E per channel, ≥ 0
//   /materials/label       int32   [nm]     row of /labels/name (only where the scene has labels)
//   /labels/name           string  [nl]     fixed-length UTF-8
//
// A material is a distinct (ρ, E, label), numbered in order of first use: a few rows for most
// scenes, so the per-triangle cost is one int32 instead of six float64.
#pragma once

#include "io/store/format_names.h"

namespace radiosity::scene_format {

inline constexpr char kKind[] = "radiosity scene";
inline constexpr int kFormatVersion = 1;

using format_names::kMesh, format_names::kVertices, format_names::kTriangles;
inline constexpr char kMaterial[] = "/mesh/material", kSourceFace[] = "/mesh/source_face";
inline constexpr char kMaterials[] = "/materials", kReflectance[] = "/materials/reflectance",
                      kEmission[] = "/materials/emission", kLabel[] = "/materials/label";
inline constexpr char kLabels[] = "/labels", kLabelName[] = "/labels/name";

/// Attribute names: of the root (`source` besides the shared ones), and of every dataset.
namespace attribute {
using namespace format_names::attribute;
inline constexpr char kSource[] = "source";
}  // namespace attribute

}  // namespace radiosity::scene_format
