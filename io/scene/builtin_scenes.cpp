// Built-in scenes, chosen with "builtin:NAME?key=value&...". Each is a test case with a known
// answer or a classic reference, so its geometry is spelled out here rather than shipped as files.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "io/core/error.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity {
namespace detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct ParamDef {
  const char* name;
  double defaultValue;
  double min, max;
  bool minExclusive = false;  ///< sizes must be > 0
  bool integer = false;
  std::vector<double> choices = {};  ///< when not empty, the only values allowed
};

using Params = std::map<std::string, double>;

/// Collects polygons into a Mesh: welds vertices with equal coordinates (so neighbours share
/// indices) and turns each polygon so that its right-hand-rule normal points along `litSide`.
class SceneBuilder {
 public:
  void addPolygon(std::vector<Vec3> corners, Vec3 litSide, const Rgb& rho, const Rgb& e) {
    Vec3 normal;  // Newell: robust for the slightly non-planar published Cornell quads
    for (size_t i = 0; i < corners.size(); ++i) {
      normal = normal + cross(corners[i], corners[(i + 1) % corners.size()]);
    }
    if (dot(normal, litSide) < 0) std::reverse(corners.begin(), corners.end());
    std::vector<int64_t> ids;
    for (const Vec3& p : corners) ids.push_back(vertexId(p));
    for (const auto& t : triangulatePolygon(corners)) {
      mesh_.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
      mesh_.sourceFace.push_back(faces_);
      mesh_.reflectance.push_back(rho);
      mesh_.emission.push_back(e);
      mesh_.label.push_back(label_);
    }
    ++faces_;
  }
  /// Labels the polygons added from now on (for messages such as the winding warning).
  void setLabel(const std::string& name) {
    const auto it = std::find(mesh_.labelNames.begin(), mesh_.labelNames.end(), name);
    label_ = static_cast<int32_t>(it - mesh_.labelNames.begin());
    if (it == mesh_.labelNames.end()) mesh_.labelNames.push_back(name);
  }
  void addTriangle(Vec3 a, Vec3 b, Vec3 c, Vec3 litSide, const Rgb& rho, const Rgb& e) {
    addPolygon({a, b, c}, litSide, rho, e);
  }
  /// The mesh; without labels if setLabel() was never called, else polygons added before the
  /// first setLabel() are labelled 'unnamed'.
  Mesh take() {
    if (mesh_.labelNames.empty()) {
      mesh_.label.clear();
    } else if (std::find(mesh_.label.begin(), mesh_.label.end(), -1) != mesh_.label.end()) {
      setLabel("unnamed");
      std::replace(mesh_.label.begin(), mesh_.label.end(), -1, label_);
    }
    return std::move(mesh_);
  }

 private:
  int64_t vertexId(Vec3 p) {
    const auto [it, added] = ids_.emplace(std::array<double, 3>{p.x, p.y, p.z}, ids_.size());
    if (added) mesh_.vertices.push_back(p);
    return it->second;
  }

  Mesh mesh_;
  std::map<std::array<double, 3>, int64_t> ids_;
  int64_t faces_ = 0;
  int32_t label_ = -1;  ///< -1: no label set yet
};

Vec3 centroid(const std::vector<Vec3>& points) {
  Vec3 sum;
  for (const Vec3& p : points) sum = sum + p;
  return (1.0 / static_cast<double>(points.size())) * sum;
}

Rgb grey(double v) { return {v, v, v}; }

/// The floor y = 0 of the Cornell box with the blocks' footprints cut out, as convex pieces: the
/// floor under a block is never lit, and a patch that reached under one would spread that
/// darkness over its lit part (the light beside the blocks' feet came out 7–14 % low, measured
/// by `radiosity verify`). Cut in slabs z ∈ [z_k, z_k+1] at every corner's z, where each
/// boundary (the floor's sides, the footprints' sides) is a straight line in x, so each slab
/// splits into quads.
void cornellFloor(SceneBuilder& b, const std::vector<Vec3>& floor,
                  const std::vector<std::vector<Vec3>>& holes, const Rgb& rho) {
  // x-interval of a convex polygon on the line z = at, if it meets it.
  auto across = [](const std::vector<Vec3>& polygon, double at) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t k = 0; k < polygon.size(); ++k) {
      const Vec3 a = polygon[k], c = polygon[(k + 1) % polygon.size()];
      if ((a.z - at) * (c.z - at) > 0) continue;
      const double x = a.z == c.z ? a.x : a.x + (c.x - a.x) * (at - a.z) / (c.z - a.z);
      const double x2 = a.z == c.z ? c.x : x;
      lo = std::min({lo, x, x2}), hi = std::max({hi, x, x2});
    }
    return std::pair{lo, hi};
  };
  std::vector<double> zs;
  for (const Vec3& v : floor) zs.push_back(v.z);
  for (const auto& hole : holes)
    for (const Vec3& v : hole) zs.push_back(v.z);
  std::sort(zs.begin(), zs.end());
  zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
  for (size_t k = 0; k + 1 < zs.size(); ++k) {
    const double za = zs[k], zb = zs[k + 1], middle = (za + zb) / 2;
    // The boundaries inside the slab, left to right, each as its x at za and zb.
    std::vector<std::array<double, 2>> left, right;
    const auto [fa, fa2] = across(floor, za);
    const auto [fb, fb2] = across(floor, zb);
    left.push_back({fa, fb});
    std::vector<std::pair<double, size_t>> order;
    for (size_t h = 0; h < holes.size(); ++h) {
      const auto [lo, hi] = across(holes[h], middle);
      if (lo <= hi) order.emplace_back(lo, h);
    }
    std::sort(order.begin(), order.end());
    for (const auto& [unused, h] : order) {
      const auto [la, ha] = across(holes[h], za);
      const auto [lb, hb] = across(holes[h], zb);
      right.push_back({la, lb});
      left.push_back({ha, hb});
    }
    right.push_back({fa2, fb2});
    for (size_t piece = 0; piece < left.size(); ++piece) {
      std::vector<Vec3> corners = {{left[piece][0], 0, za}, {left[piece][1], 0, zb},
                                   {right[piece][1], 0, zb}, {right[piece][0], 0, za}};
      auto same = [](const Vec3& u, const Vec3& v) { return u.x == v.x && u.z == v.z; };
      corners.erase(std::unique(corners.begin(), corners.end(), same), corners.end());
      if (corners.size() > 3 && same(corners.back(), corners.front())) corners.pop_back();
      if (corners.size() >= 3) b.addPolygon(corners, {0, 1, 0}, rho, {0, 0, 0});
    }
  }
}

/// The Cornell box as measured (Cornell University Program of Computer Graphics, "Cornell Box
/// Data"), in mm. Source faces: 0 floor; 1–9 ceiling cells, row by row in z then x, cell 5 being
/// the light; 10 back wall; 11 right wall (green, x = 0); 12 left wall (red); 13 short block top,
/// 14–17 its sides; 18 tall block top, 19–22 its sides. Block bottoms are left out (unseen).
/// `scale` multiplies every coordinate (1: mm).
Mesh cornell(const Params& p) {
  const Rgb white = {0.725, 0.71, 0.68}, red = {0.63, 0.065, 0.05}, green = {0.14, 0.45, 0.091};
  const double pi = std::numbers::pi;
  const Rgb light = {pi * 17 * p.at("light"), pi * 12 * p.at("light"), pi * 4 * p.at("light")};
  const Rgb none = {0, 0, 0};
  const Vec3 boxCentre = {278, 274, 280};
  SceneBuilder b;
  auto wall = [&](std::vector<Vec3> q, const Rgb& rho, const Rgb& e) {
    const Vec3 inward = boxCentre - centroid(q);
    b.addPolygon(std::move(q), inward, rho, e);
  };
  b.setLabel("floor");
  cornellFloor(b, {{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}},
               {{{130, 0, 65}, {290, 0, 114}, {240, 0, 272}, {82, 0, 225}},
                {{423, 0, 247}, {472, 0, 406}, {314, 0, 456}, {265, 0, 296}}},
               white);
  // The ceiling is rectangular; cutting it at the light's edges keeps the mesh conforming
  // instead of overlapping the light with the ceiling.
  const double xs[] = {0, 213, 343, 556}, zs[] = {0, 227, 332, 559.2}, y = 548.8;
  for (int iz = 0; iz < 3; ++iz) {
    for (int ix = 0; ix < 3; ++ix) {
      const bool isLight = ix == 1 && iz == 1;
      b.setLabel(isLight ? "light" : "ceiling");
      wall({{xs[ix], y, zs[iz]},
            {xs[ix + 1], y, zs[iz]},
            {xs[ix + 1], y, zs[iz + 1]},
            {xs[ix], y, zs[iz + 1]}},
           white, isLight ? light : none);
    }
  }
  b.setLabel("back wall");
  wall({{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}, white, none);
  b.setLabel("green wall");
  wall({{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}, green, none);
  b.setLabel("red wall");
  wall({{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}, red, none);

  auto block = [&](const std::vector<std::vector<Vec3>>& faces) {
    std::vector<Vec3> all;
    for (const auto& f : faces) all.insert(all.end(), f.begin(), f.end());
    const Vec3 centre = centroid(all);
    for (const auto& f : faces) b.addPolygon(f, centroid(f) - centre, white, none);
  };
  b.setLabel("short block");
  block({{{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}},
         {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}},
         {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}},
         {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}},
         {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}}});
  b.setLabel("tall block");
  block({{{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}},
         {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}},
         {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}},
         {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}},
         {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}});
  // Scaled once built, so that the welding and triangulation above are the same at any scale.
  Mesh mesh = b.take();
  for (Vec3& v : mesh.vertices) v = p.at("scale") * v;
  return mesh;
}

/// A closed cube [0, size]³ seen from inside, uniform ρ and E: in such an enclosure
/// B = E / (1 − ρ) exactly. Source faces: x = 0, x = size, y = 0, y = size, z = 0, z = size.
Mesh box(const Params& p) {
  const double s = p.at("size");
  const Vec3 centre = {s / 2, s / 2, s / 2};
  SceneBuilder b;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double side : {0.0, s}) {
      std::vector<Vec3> q(4);
      for (int k = 0; k < 4; ++k) {
        q[k][axis] = side;
        q[k][u] = (k == 1 || k == 2) ? s : 0;
        q[k][v] = (k >= 2) ? s : 0;
      }
      const Vec3 inward = centre - centroid(q);
      b.setLabel(std::string("wall ") + "xyz"[axis] + (side == 0 ? " = 0" : " = size"));
      b.addPolygon(std::move(q), inward, grey(p.at("rho")), grey(p.at("e")));
    }
  }
  return b.take();
}

/// Two width × height rectangles with closed-form view factors. angle = 0: parallel, facing
/// each other at `distance` (unit squares at distance 1: F = 0.19982). angle = 90: sharing the
/// edge y = 0 (length width), the emitter on the floor z = 0, the receiver standing in the
/// plane y = 0 (height along z). Source faces: 0 emitter (z = 0), 1 receiver.
Mesh plates(const Params& p) {
  const double w = p.at("width"), h = p.at("height"), d = p.at("distance");
  SceneBuilder b;
  b.setLabel("emitter");
  b.addPolygon({{0, 0, 0}, {w, 0, 0}, {w, h, 0}, {0, h, 0}}, {0, 0, 1}, grey(p.at("rho_emitter")),
               grey(p.at("e")));
  b.setLabel("receiver");
  if (p.at("angle") == 0) {
    b.addPolygon({{0, 0, d}, {w, 0, d}, {w, h, d}, {0, h, d}}, {0, 0, -1}, grey(p.at("rho")),
                 grey(0));
  } else {
    if (d != 1) {
      throw InputError("builtin:plates: parameter 'distance' applies to angle=0 only");
    }
    b.addPolygon({{0, 0, 0}, {w, 0, 0}, {w, 0, h}, {0, 0, h}}, {0, 1, 0}, grey(p.at("rho")),
                 grey(0));
  }
  return b.take();
}

Mesh rooms(const Params& p) {
  return buildRooms(static_cast<int64_t>(p.at("patches")), static_cast<uint64_t>(p.at("seed")),
                    p.at("light"));
}

/// An icosphere seen from inside (a closed enclosure like `box`, but with many view factors
/// and a near-singular system for ρ → 1). Source face = triangle index. `cap` in [−1, 1]: only
/// triangles whose centroid has z > cap × radius emit `e`, the others emit 0 (a spherical cap
/// of area fraction (1 − cap)/2 up to faceting); the default −1 lets every triangle emit.
Mesh sphere(const Params& p) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& x : v) x = normalize(x);
  for (int level = 0; level < static_cast<int>(p.at("level")); ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int c) {
      const auto key = std::minmax(a, c);
      const auto [it, added] = midpoint.emplace(key, static_cast<int>(v.size()));
      if (added) v.push_back(normalize(v[a] + v[c]));
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  const double r = p.at("radius"), cap = p.at("cap");
  SceneBuilder b;
  b.setLabel("sphere");
  for (const auto& f : faces) {
    const Vec3 a = r * v[f[0]], c = r * v[f[1]], d = r * v[f[2]];
    // cap = −1 needs no test (every centroid lies strictly inside the sphere anyway).
    const bool emits = cap <= -1 || (a.z + c.z + d.z) / 3 > cap * r;
    b.addTriangle(a, c, d, -1.0 * (a + c + d), grey(p.at("rho")), grey(emits ? p.at("e") : 0));
  }
  return b.take();
}

struct SceneDef {
  const char* name;
  std::vector<ParamDef> params;
  Mesh (*build)(const Params&);
};

const std::vector<SceneDef>& scenes() {
  static const std::vector<SceneDef> table = {
      {"box", {{"rho", 0.5, 0, 1}, {"e", 1, 0, kInf}, {"size", 1, 0, 1e30, true}}, box},
      {"cornell", {{"light", 1, 0, kInf}, {"scale", 1, 0, 1e30, true}}, cornell},
      {"plates",
       {{"e", 1, 0, kInf},
        {"rho", 0, 0, 1},
        {"rho_emitter", 0, 0, 1},
        {"distance", 1, 0, 1e30, true},
        {"width", 1, 0, 1e30, true},
        {"height", 1, 0, 1e30, true},
        {"angle", 0, 0, 90, false, true, {0, 90}}},
       plates},
      {"rooms",
       {{"patches", 10000, 1000, 1e7, false, true},
        {"seed", 1, 0, 4294967295.0, false, true},
        {"light", 10, 0, kInf}},
       rooms},
      {"sphere",
       {{"rho", 0.5, 0, 1},
        {"e", 1, 0, kInf},
        {"radius", 1, 0, 1e30, true},
        {"level", 2, 0, 7, false, true},
        {"cap", -1, -1, 1}},
       sphere},
  };
  return table;
}

std::string formatNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// Reads "key=value&..." against the scene's parameter list; unknown keys are errors, as a
/// misspelt parameter silently ignored would give a different scene than the user asked for.
Params parseParams(const std::string& spec, const SceneDef& scene, std::string_view query) {
  Params params;
  for (const ParamDef& def : scene.params) params[def.name] = def.defaultValue;
  std::string known;
  for (const ParamDef& def : scene.params)
    known += (known.empty() ? "" : ", ") + std::string(def.name);
  std::map<std::string, bool> given;
  while (!query.empty()) {
    const size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      throw InputError(spec + ": malformed parameter '" + std::string(pair) +
                       "' (expected key=value)");
    }
    const std::string key(pair.substr(0, eq));
    const std::string_view text = pair.substr(eq + 1);
    const auto def = std::find_if(scene.params.begin(), scene.params.end(),
                                  [&](const ParamDef& d) { return key == d.name; });
    if (def == scene.params.end()) {
      throw InputError(spec + ": unknown parameter '" + key +
                       "' (known: " + (known.empty() ? "none" : known) + ")");
    }
    if (given[key]) throw InputError(spec + ": parameter '" + key + "' given twice");
    given[key] = true;
    double value = 0;
    if (parseNumber(text, value) != NumberStatus::kOk || !std::isfinite(value)) {
      throw InputError(spec + ": parameter '" + key + "': '" + std::string(text) +
                       "' is not a finite number");
    }
    const bool belowMin = def->minExclusive ? !(value > def->min) : !(value >= def->min);
    if (belowMin || value > def->max) {
      throw InputError(spec + ": parameter '" + key + "' = " + std::string(text) +
                       " out of range " + (def->minExclusive ? "(" : "[") + formatNumber(def->min) +
                       ", " + formatNumber(def->max) + "]");
    }
    if (def->integer && value != std::floor(value)) {
      throw InputError(spec + ": parameter '" + key + "' must be an integer");
    }
    if (!def->choices.empty() &&
        std::find(def->choices.begin(), def->choices.end(), value) == def->choices.end()) {
      std::string allowed;
      for (double c : def->choices) allowed += (allowed.empty() ? "" : " or ") + formatNumber(c);
      throw InputError(spec + ": parameter '" + key + "' must be " + allowed);
    }
    params[key] = value;
  }
  return params;
}

}  // namespace

// The scene `spec` names, with its query ("key=value&...").
const SceneDef& findScene(const std::string& spec, std::string_view& query) {
  const std::string_view body = std::string_view(spec).substr(std::string_view("builtin:").size());
  const size_t question = body.find('?');
  const std::string name(body.substr(0, question));
  query = question == std::string_view::npos ? std::string_view() : body.substr(question + 1);
  for (const SceneDef& scene : scenes()) {
    if (name == scene.name) return scene;
  }
  std::string known;
  for (const SceneDef& scene : scenes())
    known += (known.empty() ? "" : ", ") + std::string(scene.name);
  throw InputError(spec + ": unknown built-in scene '" + name + "' (known: " + known + ")");
}

Mesh buildBuiltinScene(const std::string& spec) {
  std::string_view query;
  const SceneDef& scene = findScene(spec, query);
  return scene.build(parseParams(spec, scene, query));
}

}  // namespace detail

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const auto& scene : detail::scenes()) names.emplace_back(scene.name);
  return names;
}

std::optional<BuiltinSpec> parseBuiltinSpec(const std::string& spec) {
  if (spec.rfind("builtin:", 0) != 0) return std::nullopt;
  std::string_view query;
  const detail::SceneDef& scene = detail::findScene(spec, query);
  return BuiltinSpec{scene.name, detail::parseParams(spec, scene, query)};
}

}  // namespace radiosity
