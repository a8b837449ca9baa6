// The checks every scene passes, whatever it was read from: later stages rely on them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"
#include "core/shown_text.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"

namespace radiosity {
namespace {

std::string triangleLabel(size_t t) { return "triangle " + std::to_string(t); }

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

/// tracingProblem() of `mesh` in the frame of the box lo..hi, which holds its triangles (and
/// may reach farther: the triangles dropped as degenerate).
std::string tracingProblemInFrame(const Mesh& mesh, Vec3 lo, Vec3 hi) {
  Vec3 keptLo, keptHi;
  mesh.boundingBox(keptLo, keptHi);
  if (keptLo == lo && keptHi == hi) return tracingProblem(mesh);
  // A probe: the mesh and a triangle spanning the box, as large as its distance from the centre
  // (traceable itself), on a face of its own; the mesh's triangles keep their numbers.
  Mesh probe = mesh;
  const auto v = static_cast<int64_t>(probe.vertices.size());
  probe.vertices.push_back(lo);
  probe.vertices.push_back(hi);
  probe.triangles.push_back({v, v + 1, v + 1});
  probe.sourceFace.push_back(1 + *std::max_element(mesh.sourceFace.begin(), mesh.sourceFace.end()));
  const std::string problem = tracingProblem(probe);
  if (problem.empty()) return "";
  return problem +
         " (the scene's extent includes the triangles dropped as degenerate: a "
         "vertex far off?)";
}

}  // namespace

double longestEdge(const Mesh& mesh, int64_t t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k);
    longest = std::max(longest, std::hypot(e.x, e.y, e.z));  // hypot: no underflow at 1e-160
  }
  return longest;
}

bool isDegenerate(const Mesh& mesh, int64_t t) {
  // Its height over its longest edge: a triangle is judged by its own shape, never by the
  // scene's size (a room on a ground plane 1e6 wide used to lose every triangle).
  const double area = mesh.area(t), longest = longestEdge(mesh, t);
  return !(area > 0) || !(2 * (area / longest) / longest > kDegenerateHeight);
}

void validateScene(Mesh& mesh, const std::string& source) {
  const auto nt = static_cast<size_t>(mesh.triangleCount());
  if (mesh.sourceFace.size() != nt || mesh.reflectance.size() != nt || mesh.emission.size() != nt) {
    throw Error(exit_code::kFailure,
                source + ": internal error: per-triangle arrays differ in size");
  }
  if (!mesh.label.empty()) {
    if (mesh.label.size() != nt) {
      throw Error(exit_code::kFailure, source + ": internal error: labels differ in size");
    }
    for (int32_t l : mesh.label) {
      if (l < 0 || static_cast<size_t>(l) >= mesh.labelNames.size()) {
        throw Error(exit_code::kFailure,
                    source + ": internal error: label " + std::to_string(l) + " out of range");
      }
    }
  }
  // Labels are stored as UTF-8 text (result and scene files say so): a name in another
  // encoding keeps its bytes as \xNN, and the user is told which.
  for (std::string& name : mesh.labelNames) {
    std::string text = wellFormedUtf8(name);
    if (text == name) continue;
    mesh.warnings.push_back(source + ": the name '" + shownText(text, 80) +
                            "' is not UTF-8 text: stored with its other bytes as \\xNN");
    name = std::move(text);
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.vertices[v][k];
      if (!std::isfinite(x) || std::abs(x) > kMaxCoordinate) {
        throw InputError(source + ": vertex " + std::to_string(v + 1) +
                         " (counting from 1) has coordinate " + number(x) +
                         " (must be finite, |x| ≤ 1e30)");
      }
    }
  }
  const auto nv = static_cast<int64_t>(mesh.vertices.size());
  for (size_t t = 0; t < nt; ++t) {
    for (int64_t i : mesh.triangles[t]) {
      if (i < 0 || i >= nv) {
        throw InputError(source + ": " + triangleLabel(t) + " refers to vertex index " +
                         std::to_string(i) + " (" + std::to_string(nv) + " vertices)");
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double rho = mesh.reflectance[t][c];
      if (!(rho >= 0 && rho <= 1)) {  // also refuses NaN
        throw InputError(source + ": " + triangleLabel(t) + " has reflectance " + number(rho) +
                         " (must be within [0, 1])");
      }
      const double e = mesh.emission[t][c];
      if (!(e >= 0) || !(e <= kMaxEmission)) {
        throw InputError(source + ": " + triangleLabel(t) + " has emission " + number(e) +
                         " (must be within [0, 1e100]: radiosity is linear in E, so scale it "
                         "down and B up)");
      }
    }
  }

  // Degenerate triangles carry no area and would give NaN normals: drop them, each judged by
  // its own shape so that the rule depends neither on the units nor on the rest of the scene.
  // They stay in the tracing frame: a needle to a stray vertex far off is a vertex gone astray,
  // not a sliver, and dropping it would open the surface it closed.
  Vec3 frameLo, frameHi;
  mesh.boundingBox(frameLo, frameHi);
  size_t kept = 0;
  for (size_t t = 0; t < nt; ++t) {
    const auto at = static_cast<int64_t>(t);
    if (isDegenerate(mesh, at)) continue;
    // Smaller areas are not normal doubles: E·A and ratios of areas lose their digits.
    if (!(mesh.area(at) >= kMinArea)) {
      throw InputError(source + ": " + triangleLabel(t) + " has area " + number(mesh.area(at)) +
                       ", below what double precision holds (1e-305): scale the scene up "
                       "(the answer does not depend on the unit)");
    }
    mesh.triangles[kept] = mesh.triangles[t];
    mesh.sourceFace[kept] = mesh.sourceFace[t];
    mesh.reflectance[kept] = mesh.reflectance[t];
    mesh.emission[kept] = mesh.emission[t];
    if (!mesh.label.empty()) mesh.label[kept] = mesh.label[t];
    ++kept;
  }
  if (kept < nt) {
    mesh.warnings.push_back(source + ": dropped " + std::to_string(nt - kept) +
                            " degenerate triangle(s) (height ≤ 1e-12 × its longest edge)");
    mesh.triangles.resize(kept);
    mesh.sourceFace.resize(kept);
    mesh.reflectance.resize(kept);
    mesh.emission.resize(kept);
    if (!mesh.label.empty()) mesh.label.resize(kept);
  }
  if (kept == 0) throw InputError(source + ": scene has no triangles");
  if (const std::string problem = tracingProblemInFrame(mesh, frameLo, frameHi); !problem.empty())
    throw InputError(source + ": " + problem);
}

}  // namespace radiosity
