// render: a result file → a picture. Camera rays through the patches (formfactor's tracer),
// radiance B/π per pixel, smoothly interpolated from vertex radiosity; then a PNG (auto exposure,
// sRGB tone mapping), a linear HDR PFM (the radiance itself), or a PNG false-colour map of B or
// H with a legend. Collective: the ranks share the image rows, rank 0 writes the file.
#pragma once

#include <mpi.h>

#include <optional>
#include <string>

#include "core/enum_names.h"
#include "core/vec3.h"
#include "io/store/result.h"

namespace radiosity::render {

/// The file written, by the output's extension (imageFormatOf).
enum class ImageFormat { kPng, kPfm };

/// The format `path` names: .png or .pfm, in any case. Throws Error(kUsage) for any other name,
/// naming the extensions accepted.
ImageFormat imageFormatOf(const std::string& path);

/// What a PNG shows: the picture, or a false-colour map of a quantity of the result.
enum class FalseColour { kNone, kRadiosity, kIrradiance, kTemperature, kNetHeatFlux };
inline constexpr NamedValue<FalseColour> kFalseColourNames[] = {
    {FalseColour::kRadiosity, "radiosity", "B, the exitance leaving each surface"},
    {FalseColour::kIrradiance, "irradiance",
     "H, the flux arriving per unit area: the illuminance, in lux where E is in lm/m^2"},
    {FalseColour::kTemperature, "temperature", "a thermal result's temperature, K"},
    {FalseColour::kNetHeatFlux, "net_heat_flux",
     "a thermal result's net flux leaving each surface, W/m^2 (negative where it gains heat)"},
};

/// Whether the map shows a thermal result's own quantity (its scale spans the values' range).
inline bool isThermalMap(FalseColour f) {
  return f == FalseColour::kTemperature || f == FalseColour::kNetHeatFlux;
}

/// The false-colour map's scale.
enum class Scale { kAuto, kLinear, kLog };
inline constexpr NamedValue<Scale> kScaleNames[] = {
    {Scale::kAuto, "auto", "log where the values span more than two decades"},
    {Scale::kLinear, "linear", "from 0"},
    {Scale::kLog, "log", "whole decades, at most six"},
};

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
  double exposureStops = 0;  ///< added to the automatic exposure (the PNG picture's only: else 0)
  bool smooth = true;        ///< vertex interpolation (false: flat patches)
  int samplesPerAxis = 2;    ///< antialiasing: n×n fixed subpixel samples per pixel
  /// A PNG only: a map of this quantity instead of the picture. Each pixel shows the luminance
  /// (Rec. 709 weights, which sum to 1: a grey surface's value, a thermal run's one channel)
  /// of the quantity, averaged over the pixel's samples that see a surface.
  FalseColour falseColour = FalseColour::kNone;
  Scale scale = Scale::kAuto;  ///< of the false-colour map
};

/// Renders `result` and writes `path` (on rank 0, atomically) in the format its extension names:
/// .png, the picture tone-mapped to sRGB or, with options.falseColour, the map with its legend;
/// .pfm, the radiance B/π per pixel as float32 RGB in the result's units (those of E, per
/// steradian), no exposure. Collective on `comm`: every rank passes the whole result and the same
/// options; the file does not depend on the number of ranks. Every rank returns, or every rank
/// throws the same Error (kUsage for bad options or an unknown extension, kBadInput for an
/// inconsistent result, kFailure when the file cannot be written; then no file is left and an
/// existing `path` is unchanged).
void renderImage(MPI_Comm comm, const Result& result, const Options& options,
                 const std::string& path);

}  // namespace radiosity::render
