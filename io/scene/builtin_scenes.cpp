// Built-in scenes, chosen with "builtin:NAME?key=value&...". Each is a test case with a known
// answer or a classic reference, so its geometry is spelled out here rather than shipped as files.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "core/error.h"
#include "io/scene/builtin_cornell.h"
#include "io/scene/scene.h"
#include "io/scene/scene_builder.h"
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
  Mesh mesh = buildRooms(static_cast<int64_t>(p.at("patches")), static_cast<uint64_t>(p.at("seed")),
                         p.at("light"));
  mesh.lengthUnit = std::string("m");  // (a literal assigned here trips GCC 12's -Wrestrict)
  return mesh;
}

/// builtin:city: the table has checked each parameter alone; buildCity checks them together.
Mesh city(const Params& p) {
  const CityLayout layout{static_cast<int>(p.at("buildings")),
                          p.at("street"),
                          p.at("footprint_min"),
                          p.at("footprint_max"),
                          p.at("height_min"),
                          p.at("height_max"),
                          p.at("element"),
                          static_cast<uint64_t>(p.at("seed"))};
  return buildCity(layout, {p.at("rho"), p.at("e_ground"), p.at("e_building")}, "builtin:city");
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
      {"city",
       {{"buildings", 8, 1, 1000, false, true},
        {"street", 8, 0, 1e6, true},
        {"footprint_min", 10, 0, 1e6, true},
        {"footprint_max", 16, 0, 1e6, true},
        {"height_min", 6, 0, 1e6, true},
        {"height_max", 30, 0, 1e6, true},
        {"element", 6.5, 0, 1e6, true},
        {"seed", 1, 0, 4294967295.0, false, true},
        {"rho", 0.3, 0, 1},
        {"e_ground", 1, 0, kInf},
        {"e_building", 0, 0, kInf}},
       city},
      {"cornell",
       {{"light", 1, 0, kInf},
        {"scale", 1, 0, 1e30, true},
        {"cut_floor", 1, 0, 1, false, true, {0, 1}}},
       cornell},
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
