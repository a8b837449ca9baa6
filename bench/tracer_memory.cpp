// What the ray-tracing structure of the whole scene costs a rank: resident memory before and
// after `trace::SceneTracer` is built (Embree's float vertex and index buffers, its BVH, the
// twin table), and the peak while it is built, per triangle. Every rank holds one (the whole
// scene), so this with the mesh is the memory a rank needs whatever its share of the rows.
//
//   build/bench/tracer_memory 'builtin:rooms?patches=1000000' [threads]
//
// One line: triangles, vertices, the mesh's own bytes as counted from its arrays, resident MB
// before, after and at the peak of the build, bytes per triangle kept and at the peak, and the
// build's wall time. The scene is taken as `solve` takes it at its default area bound when that
// refines nothing (as for builtin:rooms): in curve order, in its tracing frame.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"

namespace {

// VmRSS and VmHWM of this process, in bytes (Linux).
void residentBytes(double& now, double& peak) {
  std::ifstream status("/proc/self/status");
  std::string key;
  double kb;
  std::string unit;
  now = peak = 0;
  while (status >> key) {
    if (key == "VmRSS:" && status >> kb >> unit)
      now = kb * 1024;
    else if (key == "VmHWM:" && status >> kb >> unit)
      peak = kb * 1024;
  }
}

// Lowers VmHWM to the current resident set, so that the next peak is the build's own.
void resetPeak() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace radiosity;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE [threads]\n", argv[0]);
    return 2;
  }
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  Mesh patches = partition::orderAlongCurve(loadScene(argv[1]));
  normaliseForTracing(patches);
  const double triangles = static_cast<double>(patches.triangleCount());
  const double vertices = static_cast<double>(patches.vertices.size());
  const double meshBytes =
      sizeof(patches.vertices[0]) * vertices +
      (sizeof(patches.triangles[0]) + sizeof(patches.reflectance[0]) +
       sizeof(patches.emission[0])) *
          triangles +
      sizeof(patches.sourceFace[0]) * static_cast<double>(patches.sourceFace.size()) +
      sizeof(patches.label[0]) * static_cast<double>(patches.label.size());

  double before, peak, after, ignored;
  resetPeak();
  residentBytes(before, ignored);
  const auto start = std::chrono::steady_clock::now();
  trace::SceneTracer tracer(patches, threads);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  residentBytes(after, peak);
  std::printf(
      "%s: %.0f triangles, %.0f vertices; mesh %.1f B per triangle; resident %.0f MB before the "
      "tracer, %.0f MB after (+%.1f B per triangle), %.0f MB at the build's peak (+%.1f B per "
      "triangle); built in %.2f s on %d thread(s)\n",
      argv[1], triangles, vertices, meshBytes / triangles, before / 1e6, after / 1e6,
      (after - before) / triangles, peak / 1e6, (peak - before) / triangles, seconds, threads);
  return 0;
}
