// renderToPng in its stages: check the input, trace this rank's rows, sum the image on rank 0,
// expose and tone map there, write the PNG, and agree on the outcome.
#include "render/render.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/corner_radiosity.h"
#include "io/store/collective.h"
#include "render/camera.h"
#include "render/png_writer.h"
#include "trace/trace.h"

namespace radiosity::render {

namespace {

constexpr int kMaxImageSide = 16384;  // keeps every MPI count below INT_MAX
constexpr int kMaxSamplesPerAxis = 16;
constexpr int kMaxBackFaces = 16;             // back faces a camera ray may pass through
constexpr double kExposurePercentile = 0.97;  // this luminance of the lit pixels ...
constexpr double kExposureTarget = 0.85;      // ... maps to this display value

// The linear image: per pixel the radiance R, G, B and the fraction of samples that hit.
constexpr int kChannels = 4;
using LinearImage = std::vector<float>;

void checkOptions(const Options& options) {
  auto usage = [](const std::string& what) { return Error(exit_code::kUsage, "render: " + what); };
  if (options.width < 1 || options.width > kMaxImageSide || options.height < 1 ||
      options.height > kMaxImageSide)
    throw usage("the image size must be between 1 and " + std::to_string(kMaxImageSide) +
                " pixels a side");
  if (options.samplesPerAxis < 1 || options.samplesPerAxis > kMaxSamplesPerAxis)
    throw usage("samples per axis must be between 1 and " + std::to_string(kMaxSamplesPerAxis));
  if (!std::isfinite(options.exposureStops)) throw usage("the exposure must be a finite number");
}

void checkResult(const Result& result) {
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
  for (const Rgb& b : result.radiosity)
    for (double c : b)
      if (!std::isfinite(c)) throw bad("holds a radiosity that is not a finite number");
  if (const std::string problem = tracingProblem(mesh); !problem.empty())
    throw bad("cannot be traced: " + problem);
}

// What a camera ray needs to know about the patches.
struct Shading {
  std::vector<Vec3> normal;
  std::vector<Rgb> radiance;       ///< flat: B/π per patch
  CornerRadiosity cornerRadiance;  ///< smooth: B/π per patch corner (empty when flat)
};

Shading makeShading(const Result& result, bool smooth) {
  const Mesh& mesh = result.mesh;
  const int64_t n = mesh.triangleCount();
  Shading shading;
  // Results read from a file carry normals and areas; results built in memory may not.
  shading.normal = result.normal;
  if (shading.normal.empty())
    for (int64_t t = 0; t < n; ++t) shading.normal.push_back(mesh.normal(t));
  shading.radiance = result.radiosity;
  for (Rgb& l : shading.radiance)
    for (double& c : l) c /= std::numbers::pi;
  if (smooth) {
    std::vector<double> area = result.area;
    if (area.empty())
      for (int64_t t = 0; t < n; ++t) area.push_back(mesh.area(t));
    // Smooth within a material only: a light beside its ceiling must not glow onto it; nor the
    // floor hidden under a block darken the lit floor at its foot.
    shading.cornerRadiance = cornerRadiosity(mesh, shading.normal, area, shading.radiance,
                                             setApart(materialSurfaces(mesh), result.hidden));
  }
  return shading;
}

// The radiance seen along one camera ray, or nothing when it leaves the scene. Back faces are
// passed through, so a camera outside a closed box sees its inside.
std::optional<Rgb> traceCameraRay(const trace::SceneTracer& tracer, const Shading& shading,
                                  Vec3 eye, Vec3 direction) {
  double tNear = 0;
  for (int crossing = 0; crossing <= kMaxBackFaces; ++crossing) {
    auto hit = tracer.intersect(eye, direction, tNear);
    if (!hit) return std::nullopt;
    if (dot(direction, shading.normal[hit->patch]) <= 0) {
      if (shading.cornerRadiance.empty()) return shading.radiance[hit->patch];
      return interpolate(shading.cornerRadiance[hit->patch], hit->u, hit->v);
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
  Shading shading = makeShading(result, options.smooth);
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
          auto radiance = traceCameraRay(tracer, shading, camera.eye, direction);
          if (!radiance) continue;
          for (int c = 0; c < 3; ++c) sum[c] += (*radiance)[c];
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

}  // namespace

void renderToPng(MPI_Comm comm, const Result& result, const Options& options,
                 const std::string& pngPath) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);

  LinearImage image;
  runCollectively(comm, [&] {
    checkOptions(options);
    checkResult(result);
    image = traceRows(result, options, rank, ranks);
  });

  // Exposure needs the whole picture, so sum first: then it is the same for any rank count.
  const int count = static_cast<int>(image.size());
  MPI_Reduce(rank == 0 ? MPI_IN_PLACE : image.data(), image.data(), count, MPI_FLOAT, MPI_SUM, 0,
             comm);

  runCollectively(comm, [&] {
    if (rank != 0) return;
    writePngRgb8(pngPath, options.width, options.height, toneMap(image, options.exposureStops));
  });
}

}  // namespace radiosity::render
