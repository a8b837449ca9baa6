#include "core/corner_radiosity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

namespace radiosity {

namespace {

// One id per distinct vertex position: meshes written by other tools may repeat a vertex for
// each face, and smoothing must still see the faces as neighbours.
std::vector<int64_t> weldByPosition(const std::vector<Vec3>& vertices) {
  std::vector<int64_t> order(vertices.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int64_t>(i);
  auto key = [&](int64_t i) {
    const Vec3& p = vertices[i];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return key(a) < key(b); });
  std::vector<int64_t> id(vertices.size());
  int64_t next = -1;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || key(order[k]) != key(order[k - 1])) ++next;
    id[order[k]] = next;
  }
  return id;
}

// The patches around each (welded) vertex v, in CSR form: patches[start[v] .. start[v + 1]).
struct VertexFans {
  std::vector<int64_t> start, patches;
};

VertexFans patchesAroundVertices(const Mesh& mesh, const std::vector<int64_t>& welded) {
  int64_t vertexCount = 0;
  for (int64_t id : welded) vertexCount = std::max(vertexCount, id + 1);
  VertexFans fans;
  fans.start.assign(vertexCount + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int64_t v : t) ++fans.start[welded[v] + 1];
  for (int64_t v = 0; v < vertexCount; ++v) fans.start[v + 1] += fans.start[v];
  fans.patches.resize(fans.start.back());
  std::vector<int64_t> fill(fans.start.begin(), fans.start.end() - 1);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    for (int64_t v : mesh.triangles[t]) fans.patches[fill[welded[v]]++] = t;
  return fans;
}

// The area-weighted mean of `value` over the patches of `fan` that `joins` admits; `own` where
// they have no area at all.
template <class Joins>
Rgb areaMean(const int64_t* fan, const int64_t* fanEnd, const Joins& joins,
             const std::vector<double>& area, const std::vector<Rgb>& value, const Rgb& own) {
  Rgb sum{0, 0, 0};
  double weight = 0;
  for (const int64_t* s = fan; s != fanEnd; ++s) {
    if (!joins(*s)) continue;
    for (int c = 0; c < 3; ++c) sum[c] += area[*s] * value[*s][c];
    weight += area[*s];
  }
  if (!(weight > 0)) return own;
  if (std::isfinite(sum[0] + sum[1] + sum[2])) {
    for (double& c : sum) c /= weight;
    return sum;
  }
  // B near the largest double overflows the sum: the mean again, from shares of the weight.
  Rgb mean{0, 0, 0};
  for (const int64_t* s = fan; s != fanEnd; ++s)
    if (joins(*s))
      for (int c = 0; c < 3; ++c) mean[c] += area[*s] / weight * value[*s][c];
  return mean;
}

// Throws std::invalid_argument (naming `caller`) unless there is a surface id per triangle.
void checkSurfaceIds(const char* caller, const Mesh& mesh, const SurfaceIds& surfaceOf) {
  if (surfaceOf.size() != mesh.triangles.size())
    throw std::invalid_argument(std::string(caller) + ": " + std::to_string(mesh.triangleCount()) +
                                " triangles but " + std::to_string(surfaceOf.size()) +
                                " surface ids");
}

// The patches around each corner, and which of them smoothing joins: those of the same surface
// whose normals lie at most the crease angle apart.
struct SmoothNeighbours {
  SmoothNeighbours(const Mesh& mesh, const std::vector<Vec3>* normal, const SurfaceIds& surfaceOf,
                   double creaseDegrees)
      : welded(weldByPosition(mesh.vertices)),
        fans(patchesAroundVertices(mesh, welded)),
        mesh(mesh),
        normal(normal),
        surfaceOf(surfaceOf),
        // A small tolerance so that exactly coplanar neighbours never drop out by rounding.
        minCos(std::cos(creaseDegrees * std::numbers::pi / 180) - 1e-9) {}

  /// Patch s's normal: the caller's, or the mesh's (no array of the whole scene's normals).
  Vec3 normalOf(int64_t s) const { return normal ? (*normal)[s] : mesh.normal(s); }

  /// Whether patches s and t are of one smooth surface.
  bool smooth(int64_t s, int64_t t) const {
    return surfaceOf[s] == surfaceOf[t] && dot(normalOf(s), normalOf(t)) >= minCos;
  }

  const std::vector<int64_t> welded;  ///< per vertex, its position's id
  const VertexFans fans;              ///< the patches around each welded vertex
  const Mesh& mesh;
  const std::vector<Vec3>* normal;
  const SurfaceIds& surfaceOf;
  const double minCos;
};

}  // namespace

SurfaceIds setApart(SurfaceIds ids, const std::vector<uint8_t>& apart) {
  // Ids of their own below every id a surface can have (materialSurfaces counts from 0).
  for (size_t t = 0; t < apart.size() && t < ids.size(); ++t)
    if (apart[t]) ids[t] = -1 - static_cast<int64_t>(t);
  return ids;
}

SurfaceIds materialSurfaces(const Mesh& mesh) {
  const int64_t n = mesh.triangleCount();
  if (mesh.reflectance.size() != mesh.triangles.size() ||
      mesh.emission.size() != mesh.triangles.size())
    throw std::invalid_argument("materialSurfaces: " + std::to_string(n) + " triangles but " +
                                std::to_string(mesh.reflectance.size()) + " reflectances and " +
                                std::to_string(mesh.emission.size()) + " emissions");
  // Few distinct materials, so a map from (ρ, E) to its id stays small.
  std::map<std::array<double, 6>, int64_t> idOf;
  SurfaceIds id(n);
  for (int64_t t = 0; t < n; ++t) {
    const Rgb &rho = mesh.reflectance[t], &e = mesh.emission[t];
    const std::array<double, 6> key = {rho[0], rho[1], rho[2], e[0], e[1], e[2]};
    id[t] = idOf.emplace(key, static_cast<int64_t>(idOf.size())).first->second;
  }
  return id;
}

CornerRadiosity cornerRadiosity(const Mesh& mesh, const std::vector<Vec3>& normal,
                                const std::vector<double>& area, const std::vector<Rgb>& value,
                                const SurfaceIds& surfaceOf, double creaseDegrees) {
  checkSurfaceIds("cornerRadiosity", mesh, surfaceOf);
  const SmoothNeighbours around(mesh, &normal, surfaceOf, creaseDegrees);
  const int64_t n = mesh.triangleCount();
  const VertexFans& fans = around.fans;
  CornerRadiosity out(n);
  for (int64_t t = 0; t < n; ++t) {
    auto joins = [&](int64_t s) { return s == t || around.smooth(s, t); };
    for (int k = 0; k < 3; ++k) {
      const int64_t v = around.welded[mesh.triangles[t][k]];
      const int64_t* fan = fans.patches.data();
      out[t][k] =
          areaMean(fan + fans.start[v], fan + fans.start[v + 1], joins, area, value, value[t]);
    }
  }
  return out;
}

struct GradientFit::Neighbours : SmoothNeighbours {
  using SmoothNeighbours::SmoothNeighbours;
};

GradientFit::GradientFit(const Mesh& mesh, const std::vector<Vec3>& normal,
                         const SurfaceIds& surfaceOf, double creaseDegrees)
    : mesh_(mesh) {
  checkSurfaceIds("GradientFit", mesh, surfaceOf);
  around_ = std::make_unique<Neighbours>(mesh, &normal, surfaceOf, creaseDegrees);
}

GradientFit::GradientFit(const Mesh& mesh, const SurfaceIds& surfaceOf, double creaseDegrees)
    : mesh_(mesh) {
  checkSurfaceIds("GradientFit", mesh, surfaceOf);
  around_ = std::make_unique<Neighbours>(mesh, nullptr, surfaceOf, creaseDegrees);
}

GradientFit::~GradientFit() = default;

std::array<Vec3, 3> GradientFit::operator()(int64_t t, const std::vector<Rgb>& value) const {
  const Mesh& mesh = mesh_;
  const VertexFans& fans = around_->fans;
  std::array<Vec3, 3> out{Vec3{0, 0, 0}, Vec3{0, 0, 0}, Vec3{0, 0, 0}};
  auto centroid = [&](int64_t p) {
    const Triangle& c = mesh.triangles[p];
    return (1.0 / 3) * (mesh.vertices[c[0]] + mesh.vertices[c[1]] + mesh.vertices[c[2]]);
  };
  std::vector<int64_t> neighbours;
  for (int64_t corner : mesh.triangles[t]) {
    const int64_t v = around_->welded[corner];
    for (int64_t k = fans.start[v]; k < fans.start[v + 1]; ++k) {
      const int64_t s = fans.patches[k];
      if (s != t && around_->smooth(s, t)) neighbours.push_back(s);
    }
  }
  std::sort(neighbours.begin(), neighbours.end());
  neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  // A basis of the patch's plane; the neighbours' offsets projected onto it.
  const Triangle& c = mesh.triangles[t];
  const Vec3 edge = mesh.vertices[c[1]] - mesh.vertices[c[0]];
  if (!(length(edge) > 0)) return out;
  const Vec3 e1 = (1 / length(edge)) * edge, e2 = cross(around_->normalOf(t), e1);
  double a11 = 0, a12 = 0, a22 = 0;
  std::array<std::array<double, 2>, 3> rhs{};
  const Vec3 here = centroid(t);
  for (int64_t s : neighbours) {
    const Vec3 d = centroid(s) - here;
    const double x = dot(d, e1), y = dot(d, e2), r2 = x * x + y * y;
    if (!(r2 > 0)) continue;
    const double w = 1 / r2;
    a11 += w * x * x, a12 += w * x * y, a22 += w * y * y;
    for (int ch = 0; ch < 3; ++ch) {
      const double dv = value[s][ch] - value[t][ch];
      rhs[ch][0] += w * x * dv, rhs[ch][1] += w * y * dv;
    }
  }
  // The normal equations, dimensionless (each weighted term is a squared cosine): a
  // determinant near zero means the neighbours lie along one line, and only that slope is
  // known; it is taken alone.
  const double det = a11 * a22 - a12 * a12, trace = a11 + a22;
  for (int ch = 0; ch < 3; ++ch) {
    double gx = 0, gy = 0;
    if (det > 1e-6 * trace * trace) {
      gx = (a22 * rhs[ch][0] - a12 * rhs[ch][1]) / det;
      gy = (a11 * rhs[ch][1] - a12 * rhs[ch][0]) / det;
    } else if (trace > 0) {  // along the one direction: A is rank one, its pseudo-inverse A/tr²
      gx = (a11 * rhs[ch][0] + a12 * rhs[ch][1]) / (trace * trace);
      gy = (a12 * rhs[ch][0] + a22 * rhs[ch][1]) / (trace * trace);
    }
    if (std::isfinite(gx) && std::isfinite(gy)) out[ch] = gx * e1 + gy * e2;
  }
  return out;
}

PatchGradients patchGradients(const Mesh& mesh, const std::vector<Vec3>& normal,
                              const std::vector<Rgb>& value, const SurfaceIds& surfaceOf,
                              int64_t first, int64_t last, double creaseDegrees) {
  const int64_t n = mesh.triangleCount();
  if (last < 0) last = n;
  if (first < 0 || first > last || last > n)
    throw std::invalid_argument("patchGradients: patches [" + std::to_string(first) + ", " +
                                std::to_string(last) + ") of " + std::to_string(n));
  const GradientFit fit(mesh, normal, surfaceOf, creaseDegrees);
  PatchGradients out(last - first);
  for (int64_t t = first; t < last; ++t) out[t - first] = fit(t, value);
  return out;
}

DisplayMesh displayMesh(const Mesh& mesh, const CornerRadiosity& corners) {
  const std::vector<int64_t> welded = weldByPosition(mesh.vertices);
  const int64_t n = mesh.triangleCount();
  // Corners t·3 + k in the order of (welded vertex, value); equal neighbours become one vertex.
  auto key = [&](int64_t corner) {
    const Rgb& b = corners[corner / 3][corner % 3];
    return std::make_tuple(welded[mesh.triangles[corner / 3][corner % 3]], b[0], b[1], b[2]);
  };
  std::vector<int64_t> order(3 * n);
  for (int64_t c = 0; c < 3 * n; ++c) order[c] = c;
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
  DisplayMesh out;
  out.triangles.resize(n);
  // (reserved to the count, not grown by doubling: a 10^6-patch result's arrays are written by
  // one rank, and the doubling's spare and moved copies set the write's peak)
  int64_t distinct = 0;
  for (size_t i = 0; i < order.size(); ++i)
    distinct += i == 0 || key(order[i - 1]) != key(order[i]) ? 1 : 0;
  out.vertices.reserve(distinct);
  out.radiosity.reserve(distinct);
  for (size_t i = 0; i < order.size(); ++i) {
    const int64_t c = order[i];
    if (i == 0 || key(order[i - 1]) != key(c)) {
      out.vertices.push_back(mesh.vertices[mesh.triangles[c / 3][c % 3]]);
      out.radiosity.push_back(corners[c / 3][c % 3]);
    }
    out.triangles[c / 3][c % 3] = static_cast<int64_t>(out.vertices.size()) - 1;
  }
  return out;
}

}  // namespace radiosity
