#include "core/corner_radiosity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

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

// Of the corners of patches [first, last) only (last < 0: of every patch); the other vertices'
// fans are empty.
VertexFans patchesAroundVertices(const Mesh& mesh, const std::vector<int64_t>& welded,
                                 int64_t first = 0, int64_t last = -1) {
  int64_t vertexCount = 0;
  for (int64_t id : welded) vertexCount = std::max(vertexCount, id + 1);
  std::vector<uint8_t> wanted;
  if (last >= 0) {
    wanted.assign(vertexCount, 0);
    for (int64_t t = first; t < last; ++t)
      for (int64_t v : mesh.triangles[t]) wanted[welded[v]] = 1;
  }
  auto kept = [&](int64_t v) { return wanted.empty() || wanted[welded[v]]; };
  VertexFans fans;
  fans.start.assign(vertexCount + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int64_t v : t)
      if (kept(v)) ++fans.start[welded[v] + 1];
  for (int64_t v = 0; v < vertexCount; ++v) fans.start[v + 1] += fans.start[v];
  fans.patches.resize(fans.start.back());
  std::vector<int64_t> fill(fans.start.begin(), fans.start.end() - 1);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    for (int64_t v : mesh.triangles[t])
      if (kept(v)) fans.patches[fill[welded[v]]++] = t;
  return fans;
}

// The area-weighted mean of `value` over the patches of `fan` that `joins` admits; `own` where
// they have no area at all.
template <class Joins, class Areas, class Values>
Rgb areaMean(const int64_t* fan, const int64_t* fanEnd, const Joins& joins, const Areas& area,
             const Values& value, const Rgb& own) {
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

// Throws std::invalid_argument (naming `caller`) unless [first, last) are patches of `mesh`.
void checkRange(const char* caller, const Mesh& mesh, int64_t first, int64_t last) {
  if (first < 0 || first > last || last > mesh.triangleCount())
    throw std::invalid_argument(std::string(caller) + ": patches [" + std::to_string(first) + ", " +
                                std::to_string(last) + ") of " +
                                std::to_string(mesh.triangleCount()));
}

// The patches around each corner, and which of them smoothing joins: those of the same surface
// whose normals lie at most the crease angle apart.
struct SmoothNeighbours {
  SmoothNeighbours(const Mesh& mesh, const std::vector<Vec3>* normal, const SurfaceIds& surfaceOf,
                   double creaseDegrees, int64_t first = 0, int64_t last = -1)
      : welded(weldByPosition(mesh.vertices)),
        fans(patchesAroundVertices(mesh, welded, first, last)),
        mesh(mesh),
        normal(normal),
        surfaceOf(surfaceOf),
        // A small tolerance so that exactly coplanar neighbours never drop out by rounding.
        minCos(std::cos(creaseDegrees * std::numbers::pi / 180) - 1e-9),
        first(first) {
    // (each patch's normal is read for every corner of every patch around it: computed once
    // for the patches of the range, from the mesh elsewhere)
    if (!normal && last >= 0)
      for (int64_t t = first; t < last; ++t) rangeNormal.push_back(mesh.normal(t));
  }

  /// Patch s's normal: the caller's, or the mesh's (no array of the whole scene's normals).
  Vec3 normalOf(int64_t s) const {
    if (normal) return (*normal)[s];
    const auto inRange = static_cast<uint64_t>(s - first);
    return inRange < rangeNormal.size() ? rangeNormal[inRange] : mesh.normal(s);
  }

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
  const int64_t first;
  std::vector<Vec3> rangeNormal;  ///< of patches [first, last), where there is no `normal`
};

// The patches outside [first, last) that share a vertex with one inside, sorted.
std::vector<int64_t> patchesAroundOutside(const SmoothNeighbours& around, int64_t first,
                                          int64_t last) {
  const VertexFans& fans = around.fans;
  std::vector<int64_t> out;
  for (int64_t t = first; t < last; ++t)
    for (int64_t corner : around.mesh.triangles[t]) {
      const int64_t v = around.welded[corner];
      for (int64_t k = fans.start[v]; k < fans.start[v + 1]; ++k)
        if (const int64_t s = fans.patches[k]; s < first || s >= last) out.push_back(s);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

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

namespace {

// The corners of patches [first, last), entry t − first.
template <class Areas, class Values>
CornerRadiosity cornersOf(const SmoothNeighbours& around, const Areas& area, const Values& value,
                          int64_t first, int64_t last) {
  const Mesh& mesh = around.mesh;
  const VertexFans& fans = around.fans;
  CornerRadiosity out(last - first);
  for (int64_t t = first; t < last; ++t) {
    auto joins = [&](int64_t s) { return s == t || around.smooth(s, t); };
    for (int k = 0; k < 3; ++k) {
      const int64_t v = around.welded[mesh.triangles[t][k]];
      const int64_t* fan = fans.patches.data();
      out[t - first][k] =
          areaMean(fan + fans.start[v], fan + fans.start[v + 1], joins, area, value, value[t]);
    }
  }
  return out;
}

// The display mesh of patches [first, last) from their corners (entry t − first), its vertices
// numbered from 0: corners in the order of (welded vertex, value), equal neighbours one vertex.
DisplayMesh displayOf(const Mesh& mesh, const std::vector<int64_t>& welded,
                      const CornerRadiosity& corners, int64_t first, int64_t last) {
  const int64_t n = last - first;
  // Corner c is corner c % 3 of patch first + c / 3.
  auto key = [&](int64_t corner) {
    const Rgb& b = corners[corner / 3][corner % 3];
    return std::make_tuple(welded[mesh.triangles[first + corner / 3][corner % 3]], b[0], b[1],
                           b[2]);
  };
  std::vector<int64_t> order(3 * n);
  for (int64_t c = 0; c < 3 * n; ++c) order[c] = c;
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
  DisplayMesh out;
  out.triangles.resize(n);
  // (reserved to the count, not grown by doubling: the doubling's spare and moved copies would
  // set the write's peak)
  int64_t distinct = 0;
  for (size_t i = 0; i < order.size(); ++i)
    distinct += i == 0 || key(order[i - 1]) != key(order[i]) ? 1 : 0;
  out.vertices.reserve(distinct);
  out.radiosity.reserve(distinct);
  for (size_t i = 0; i < order.size(); ++i) {
    const int64_t c = order[i];
    if (i == 0 || key(order[i - 1]) != key(c)) {
      out.vertices.push_back(mesh.vertices[mesh.triangles[first + c / 3][c % 3]]);
      out.radiosity.push_back(corners[c / 3][c % 3]);
    }
    out.triangles[c / 3][c % 3] = static_cast<int64_t>(out.vertices.size()) - 1;
  }
  return out;
}

// Each patch's area: of a range of patches from an array, of the others from the mesh.
struct RangeAreas {
  const Mesh& mesh;
  int64_t first;
  std::vector<double> area;  ///< of patches [first, first + area.size())
  double operator[](int64_t t) const {
    const auto inRange = static_cast<uint64_t>(t - first);
    return inRange < area.size() ? area[inRange] : mesh.area(t);
  }
};

}  // namespace

CornerRadiosity cornerRadiosity(const Mesh& mesh, const std::vector<Vec3>& normal,
                                const std::vector<double>& area, const std::vector<Rgb>& value,
                                const SurfaceIds& surfaceOf, double creaseDegrees) {
  checkSurfaceIds("cornerRadiosity", mesh, surfaceOf);
  const SmoothNeighbours around(mesh, &normal, surfaceOf, creaseDegrees);
  return cornersOf(around, area, value, 0, mesh.triangleCount());
}

struct CornerAverages::Neighbours : SmoothNeighbours {
  using SmoothNeighbours::SmoothNeighbours;
};

CornerAverages::CornerAverages(const Mesh& mesh, const SurfaceIds& surfaceOf, int64_t first,
                               int64_t last, double creaseDegrees)
    : first_(first), last_(last) {
  checkSurfaceIds("CornerAverages", mesh, surfaceOf);
  checkRange("CornerAverages", mesh, first, last);
  around_ = std::make_unique<Neighbours>(mesh, nullptr, surfaceOf, creaseDegrees, first, last);
}

CornerAverages::~CornerAverages() = default;

std::vector<int64_t> CornerAverages::neighboursOutside() const {
  return patchesAroundOutside(*around_, first_, last_);
}

DisplayMesh CornerAverages::displayMesh(const PatchValues& value, int64_t from, int64_t to) const {
  if (from < first_ || from > to || to > last_)
    throw std::out_of_range("CornerAverages: patches [" + std::to_string(from) + ", " +
                            std::to_string(to) + ") are not in [" + std::to_string(first_) + ", " +
                            std::to_string(last_) + ")");
  RangeAreas area{around_->mesh, from, {}};
  for (int64_t t = from; t < to; ++t) area.area.push_back(around_->mesh.area(t));
  const CornerRadiosity corners = cornersOf(*around_, area, value, from, to);
  return displayOf(around_->mesh, around_->welded, corners, from, to);
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

GradientFit::GradientFit(const Mesh& mesh, const SurfaceIds& surfaceOf, int64_t first, int64_t last,
                         double creaseDegrees)
    : mesh_(mesh), first_(first), last_(last) {
  checkSurfaceIds("GradientFit", mesh, surfaceOf);
  checkRange("GradientFit", mesh, first, last);
  around_ = std::make_unique<Neighbours>(mesh, nullptr, surfaceOf, creaseDegrees, first, last);
}

GradientFit::~GradientFit() = default;

std::vector<int64_t> GradientFit::neighboursOutside(int64_t first, int64_t last) const {
  return patchesAroundOutside(*around_, first, last);
}

PatchValues::PatchValues(int64_t first, const std::vector<Rgb>& block, std::vector<int64_t> others,
                         std::vector<Rgb> otherValues)
    : first_(first),
      block_(block),
      others_(std::move(others)),
      otherValues_(std::move(otherValues)) {
  if (others_.size() != otherValues_.size() || !std::is_sorted(others_.begin(), others_.end()))
    throw std::invalid_argument("PatchValues: other patches' ids must be sorted, one value each");
}

const Rgb& PatchValues::other(int64_t p) const {
  const auto found = std::lower_bound(others_.begin(), others_.end(), p);
  if (found == others_.end() || *found != p)
    throw std::out_of_range("PatchValues: no value of patch " + std::to_string(p));
  return otherValues_[found - others_.begin()];
}

std::array<Vec3, 3> GradientFit::operator()(int64_t t, const PatchValues& value) const {
  if (last_ >= 0 && (t < first_ || t >= last_))
    throw std::out_of_range("GradientFit: patch " + std::to_string(t) + " is not in [" +
                            std::to_string(first_) + ", " + std::to_string(last_) + ")");
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
  if (last < 0) last = mesh.triangleCount();
  checkRange("patchGradients", mesh, first, last);
  const GradientFit fit(mesh, normal, surfaceOf, creaseDegrees);
  PatchGradients out(last - first);
  for (int64_t t = first; t < last; ++t) out[t - first] = fit(t, value);
  return out;
}

DisplayMesh displayMesh(const Mesh& mesh, const CornerRadiosity& corners) {
  return displayOf(mesh, weldByPosition(mesh.vertices), corners, 0, mesh.triangleCount());
}

}  // namespace radiosity
