// renderImage in its stages: check the input, trace this rank's rows, sum the image on rank 0,
// turn it into the file's pixels there (tone map, radiance or false colour), write the file, and
// agree on the outcome.
#include "render/render.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/corner_radiosity.h"
#include "parallel/collective.h"
#include "render/camera.h"
#include "render/false_colour.h"
#include "render/pfm_writer.h"
#include "render/png_writer.h"
#include "trace/trace.h"

namespace radiosity::render {

namespace {

constexpr int kMaxImageSide = 16384;  // keeps every MPI count below INT_MAX
constexpr int kMaxSamplesPerAxis = 16;
constexpr int kMaxBackFaces = 16;             // back faces a camera ray may pass through
constexpr double kExposurePercentile = 0.97;  // this luminance of the lit pixels ...
constexpr double kExposureTarget = 0.85;      // ... maps to this display value
// The largest value shown: pixels are summed in float, and a PFM holds float.
constexpr double kLargestValue = 1e37;

// The linear image: per pixel the value shown (the radiance, or the false colour's quantity)
// R, G, B times the fraction of samples that hit, and that fraction.
constexpr int kChannels = 4;
using LinearImage = std::vector<float>;

void checkOptions(const Options& options, ImageFormat format) {
  auto usage = [](const std::string& what) { return Error(exit_code::kUsage, "render: " + what); };
  if (format != ImageFormat::kPng && options.falseColour != FalseColour::kNone)
    throw usage("a false-colour map is a PNG: name the output .png");
  if ((format != ImageFormat::kPng || options.falseColour != FalseColour::kNone) &&
      options.exposureStops != 0)
    throw usage(
        "the exposure is the tone-mapped PNG picture's: a PFM holds the radiance itself "
        "and a false-colour map has its scale");
  if (options.width < 1 || options.width > kMaxImageSide || options.height < 1 ||
      options.height > kMaxImageSide)
    throw usage("the image size must be between 1 and " + std::to_string(kMaxImageSide) +
                " pixels a side");
  if (options.samplesPerAxis < 1 || options.samplesPerAxis > kMaxSamplesPerAxis)
    throw usage("samples per axis must be between 1 and " + std::to_string(kMaxSamplesPerAxis));
  if (!std::isfinite(options.exposureStops)) throw usage("the exposure must be a finite number");
  if (options.falseColour == FalseColour::kNetHeatFlux && options.scale == Scale::kLog)
    throw usage("a net heat flux changes sign: its map takes a linear scale, not --scale log");
}

void checkValues(const std::vector<Rgb>& values, const std::string& name) {
  for (const Rgb& value : values)
    for (double c : value)
      if (!(std::abs(c) <= kLargestValue))
        throw Error(exit_code::kBadInput,
                    "render: the result holds " + name +
                        " that is not a finite number or beyond 1e37, which pixels cannot hold");
}

void checkResult(const Result& result, FalseColour falseColour) {
  auto bad = [](const std::string& what) {
    return Error(exit_code::kBadInput, "render: the result " + what);
  };
  const Mesh& mesh = result.mesh;
  const size_t n = mesh.triangles.size();
  if (n == 0) throw bad("holds no patches");
  if (result.radiosity.size() != n) throw bad("holds a radiosity for some patches only");
  if (!result.normal.empty() && result.normal.size() != n)
    throw bad("holds a normal for some patches only");
  if (!result.area.empty() && result.area.size() != n)
    throw bad("holds an area for some patches only");
  if (mesh.reflectance.size() != n || mesh.emission.size() != n)
    throw bad("holds a reflectance or emission for some patches only");
  for (const Triangle& t : mesh.triangles)
    for (int64_t v : t)
      if (v < 0 || v >= static_cast<int64_t>(mesh.vertices.size()))
        throw bad("has a triangle with a vertex index out of range");
  checkValues(result.radiosity, "a radiosity");
  if (falseColour == FalseColour::kIrradiance) {
    if (result.irradiance.size() != n) throw bad("holds an irradiance for some patches only");
    checkValues(result.irradiance, "an irradiance");
  }
  if (isThermalMap(falseColour)) {
    const bool temperature = falseColour == FalseColour::kTemperature;
    const std::vector<double>& values = temperature ? result.temperature : result.netHeatFlux;
    if (values.empty())
      throw Error(exit_code::kUsage,
                  std::string("render: --false-colour ") + nameIn(kFalseColourNames, falseColour) +
                      " is a thermal result's (solve --thermal); this one is lighting's");
    if (values.size() != n)
      throw bad(temperature ? "holds a temperature for some patches only"
                            : "holds a net heat flux for some patches only");
    for (double v : values)
      if (!(std::abs(v) <= kLargestValue))
        throw bad("holds a value that is not a finite number or beyond 1e37");
  }
  if (const std::string problem = tracingProblem(mesh); !problem.empty())
    throw bad("cannot be traced: " + problem);
}

// The value each patch shows: its radiance B/π in the picture, or the false colour's quantity.
std::vector<Rgb> patchValues(const Result& result, FalseColour falseColour) {
  if (falseColour == FalseColour::kRadiosity) return result.radiosity;
  if (falseColour == FalseColour::kIrradiance) return result.irradiance;
  if (isThermalMap(falseColour)) {  // one value: its luminance (weights summing to 1) is itself
    const std::vector<double>& values =
        falseColour == FalseColour::kTemperature ? result.temperature : result.netHeatFlux;
    std::vector<Rgb> grey;
    grey.reserve(values.size());
    for (double v : values) grey.push_back(Rgb{v, v, v});
    return grey;
  }
  std::vector<Rgb> radiance = result.radiosity;
  for (Rgb& l : radiance)
    for (double& c : l) c /= std::numbers::pi;
  return radiance;
}

// What a camera ray needs to know about the patches.
struct Shading {
  std::vector<Vec3> normal;
  std::vector<Rgb> value;       ///< flat: per patch
  CornerRadiosity cornerValue;  ///< smooth: per patch corner (empty when flat)
};

Shading makeShading(const Result& result, std::vector<Rgb> values, bool smooth) {
  const Mesh& mesh = result.mesh;
  const int64_t n = mesh.triangleCount();
  Shading shading;
  // Results read from a file carry normals and areas; results built in memory may not.
  shading.normal = result.normal;
  if (shading.normal.empty())
    for (int64_t t = 0; t < n; ++t) shading.normal.push_back(mesh.normal(t));
  shading.value = std::move(values);
  if (smooth) {
    std::vector<double> area = result.area;
    if (area.empty())
      for (int64_t t = 0; t < n; ++t) area.push_back(mesh.area(t));
    // Smooth within a material only: a light beside its ceiling must not glow onto it; nor the
    // floor hidden under a block darken the lit floor at its foot. (H does not jump there, but
    // is smoothed alike: the map then shows each surface as the picture does.)
    shading.cornerValue = cornerRadiosity(mesh, shading.normal, area, shading.value,
                                          setApart(materialSurfaces(mesh), result.hidden));
  }
  return shading;
}

// The value seen along one camera ray, or nothing when it leaves the scene. Back faces are
// passed through, so a camera outside a closed box sees its inside.
std::optional<Rgb> traceCameraRay(const trace::SceneTracer& tracer, const Shading& shading,
                                  Vec3 eye, Vec3 direction) {
  double tNear = 0;
  for (int crossing = 0; crossing <= kMaxBackFaces; ++crossing) {
    auto hit = tracer.intersect(eye, direction, tNear);
    if (!hit) return std::nullopt;
    if (dot(direction, shading.normal[hit->patch]) <= 0) {
      if (shading.cornerValue.empty()) return shading.value[hit->patch];
      return interpolate(shading.cornerValue[hit->patch], hit->u, hit->v);
    }
    // Step just past the hit: Embree works in float, so the step is relative.
    tNear = hit->distance * (1 + 1e-6) + 1e-2 * tracer.offset(hit->patch);
  }
  return std::nullopt;
}

// The farthest a camera may stand from the scene's centre, in scene sizes: Embree's float
// arithmetic holds well beyond (rays start there and must still hit triangles of size ~1e-4).
constexpr double kFarthestEye = 1e6;

// Rows rank, rank + ranks, … of the image; the other rows stay zero so that a sum over the
// ranks assembles the picture exactly.
LinearImage traceRows(const Result& result, const Options& options, int rank, int ranks) {
  const Mesh& mesh = result.mesh;
  Vec3 lo, hi;
  mesh.boundingBox(lo, hi);
  const int width = options.width, height = options.height, n = options.samplesPerAxis;
  PinholeCamera camera = makeCamera(options.camera, lo, hi, static_cast<double>(width) / height);
  Shading shading = makeShading(result, patchValues(result, options.falseColour), options.smooth);
  // Traced in the scene's own frame (core/mesh.h, TracingFrame), where Embree's float arithmetic
  // holds at any scale; a camera too far away to trace from there is refused.
  Mesh traced = mesh;
  const TracingFrame frame = normaliseForTracing(traced);
  camera.eye = frame.toFrame(camera.eye);
  if (!(length(camera.eye) <= kFarthestEye)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "render: the camera is %.3g scene sizes from the scene's centre, too far to "
                  "trace (at most %.0e): move --eye closer",
                  length(camera.eye), kFarthestEye);
    throw Error(exit_code::kUsage, text);
  }
  trace::SceneTracer tracer(traced);

  LinearImage image(static_cast<size_t>(width) * height * kChannels, 0.0f);
  const double sampleWeight = 1.0 / (n * n);
  for (int y = rank; y < height; y += ranks) {
    for (int x = 0; x < width; ++x) {
      double sum[kChannels] = {0, 0, 0, 0};
      // Fixed stratified subpixel positions: the same picture on any number of ranks.
      for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
          Vec3 direction = camera.direction(x + (sx + 0.5) / n, y + (sy + 0.5) / n, width, height);
          auto value = traceCameraRay(tracer, shading, camera.eye, direction);
          if (!value) continue;
          for (int c = 0; c < 3; ++c) sum[c] += (*value)[c];
          sum[3] += 1;
        }
      }
      float* pixel = &image[(static_cast<size_t>(y) * width + x) * kChannels];
      for (int c = 0; c < kChannels; ++c) pixel[c] = static_cast<float>(sum[c] * sampleWeight);
    }
  }
  return image;
}

// The factor that puts the chosen percentile of the lit pixels' luminance at the target.
double autoExposure(const LinearImage& image) {
  std::vector<double> lit;
  for (size_t p = 0; p < image.size(); p += kChannels)
    if (image[p + 3] > 0) lit.push_back(luminance(&image[p]));
  if (lit.empty()) return 1;
  auto at = lit.begin() + static_cast<ptrdiff_t>(kExposurePercentile * (lit.size() - 1));
  std::nth_element(lit.begin(), at, lit.end());
  double reference = *at;
  // A mostly black picture: expose for its brightest pixel instead.
  if (!(reference > 0)) reference = *std::max_element(lit.begin(), lit.end());
  return reference > 0 ? kExposureTarget / reference : 1;
}

double srgbEncode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

std::vector<uint8_t> toneMap(const LinearImage& image, double exposureStops) {
  const double scale = autoExposure(image) * std::exp2(exposureStops);
  std::vector<uint8_t> rgb;
  rgb.reserve(image.size() / kChannels * 3);
  for (size_t p = 0; p < image.size(); p += kChannels) {
    for (int c = 0; c < 3; ++c) {
      double display = srgbEncode(std::clamp(image[p + c] * scale, 0.0, 1.0));
      rgb.push_back(static_cast<uint8_t>(std::lround(255 * display)));
    }
  }
  return rgb;
}

// The PFM's pixels: the radiance R, G, B (misses black, as in the PNG).
std::vector<float> radianceOf(const LinearImage& image) {
  std::vector<float> rgb;
  rgb.reserve(image.size() / kChannels * 3);
  for (size_t p = 0; p < image.size(); p += kChannels)
    rgb.insert(rgb.end(), &image[p], &image[p + 3]);
  return rgb;
}

// The false colour's value per pixel: the luminance of the quantity over the samples that hit
// (a pixel half on the background shows the surface's value, not half of it); NaN for none.
std::vector<double> luminanceOf(const LinearImage& image) {
  std::vector<double> values;
  values.reserve(image.size() / kChannels);
  for (size_t p = 0; p < image.size(); p += kChannels)
    values.push_back(image[p + 3] > 0 ? luminance(&image[p]) / image[p + 3]
                                      : std::numeric_limits<double>::quiet_NaN());
  return values;
}

LegendText legendText(const Result& result, FalseColour falseColour) {
  LegendText text;
  text.quantity = falseColour == FalseColour::kIrradiance ? "irradiance H" : "radiosity B";
  // A lighting result's E is in the scene's unit, which the result does not name.
  text.unit = result.attributes.thermal.empty() ? "unit of E" : "W/m^2";
  if (falseColour == FalseColour::kTemperature) text = {"temperature", "K"};
  if (falseColour == FalseColour::kNetHeatFlux) text = {"net heat flux q", "W/m^2"};
  return text;
}

void writeImage(const std::string& path, ImageFormat format, const Options& options,
                const Result& result, const LinearImage& image) {
  const int width = options.width, height = options.height;
  if (format == ImageFormat::kPfm) return writePfmRgb(path, width, height, radianceOf(image));
  if (options.falseColour == FalseColour::kNone)
    return writePngRgb8(path, width, height, toneMap(image, options.exposureStops));
  const Canvas map =
      falseColourMap(luminanceOf(image), width, height, legendText(result, options.falseColour),
                     options.scale, isThermalMap(options.falseColour));
  writePngRgb8(path, map.width, map.height, map.rgb);
}

}  // namespace

ImageFormat imageFormatOf(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".png") return ImageFormat::kPng;
  if (extension == ".pfm") return ImageFormat::kPfm;
  throw Error(exit_code::kUsage,
              "render: cannot tell the image format of '" + path +
                  "': name it .png (a picture, or with --false-colour a map) or .pfm (linear "
                  "HDR radiance, float RGB)");
}

void renderImage(MPI_Comm comm, const Result& result, const Options& options,
                 const std::string& path) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);

  ImageFormat format = ImageFormat::kPng;
  LinearImage image;
  runCollectively(comm, [&] {
    format = imageFormatOf(path);
    checkOptions(options, format);
    checkResult(result, options.falseColour);
    image = traceRows(result, options, rank, ranks);
  });

  // Exposure and the false colour's scale need the whole picture, so sum first: then they are the
  // same for any rank count.
  const int count = static_cast<int>(image.size());
  MPI_Reduce(rank == 0 ? MPI_IN_PLACE : image.data(), image.data(), count, MPI_FLOAT, MPI_SUM, 0,
             comm);

  runCollectively(comm, [&] {
    if (rank == 0) writeImage(path, format, options, result, image);
  });
}

}  // namespace radiosity::render
