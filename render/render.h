// render: a result file → a PNG picture. Camera rays through the patches (formfactor's
// tracer), radiance B/π per pixel, smoothly interpolated from vertex radiosity, auto exposure
// and sRGB tone mapping. Collective: the ranks share the image rows, rank 0 writes the file.
#pragma once

#include <mpi.h>

#include <optional>
#include <string>

#include "core/vec3.h"
#include "io/store/result.h"

namespace radiosity::render {

/// A pinhole camera. The image's right is forward × up, so looking along +z with up +y puts
/// +x on the left (the classic Cornell box view: red wall left, green wall right).
struct Camera {
  /// Default: on the line through lookAt along −z, just far enough back that the whole
  /// bounding box fits the field of view (with a 5% margin).
  std::optional<Vec3> eye;
  std::optional<Vec3> lookAt;  ///< default: the centre of the bounding box
  Vec3 up{0, 1, 0};
  double fovDegrees = 40;  ///< vertical field of view
};

struct Options {
  int width = 512;
  int height = 512;
  Camera camera;
  double exposureStops = 0;  ///< added to the automatic exposure
  bool smooth = true;        ///< vertex interpolation (false: flat patches)
  int samplesPerAxis = 2;    ///< antialiasing: n×n fixed subpixel samples per pixel
};

/// Renders `result` and writes `pngPath` (on rank 0, atomically). Collective on `comm`: every
/// rank passes the whole result and the same options; the picture does not depend on the number
/// of ranks. Every rank returns, or every rank throws the same Error (kUsage for bad options,
/// kBadInput for an inconsistent result, kFailure when the file cannot be written; then no file
/// is left and an existing `pngPath` is unchanged).
void renderToPng(MPI_Comm comm, const Result& result, const Options& options,
                 const std::string& pngPath);

}  // namespace radiosity::render
