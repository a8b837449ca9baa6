// The built-in scenes ("builtin:NAME?key=value&..."): their geometry, materials, labels and
// orientation, the known answers they are built for, and bad specs refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

using testing::closedAndOriented;
using testing::expectInputError;
using testing::expectNear;
using testing::signedVolume;

TEST(Builtin, NamesAreListed) {
  const auto names = builtinSceneNames();
  for (const char* name : {"cornell", "box", "plates", "sphere", "rooms", "city"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
}

TEST(Builtin, CornellFloorAsPublishedRunsUnderTheBlocks) {
  // cut_floor=0: the floor is the published quad (two triangles, source face 0), running under
  // both blocks; the hand-cut floor is the same quad less the blocks' footprints.
  const Mesh published = loadScene("builtin:cornell?cut_floor=0");
  const Mesh handCut = loadScene("builtin:cornell");
  auto floorArea = [](const Mesh& mesh, int64_t& triangles) {
    double area = 0;
    triangles = 0;
    for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
      if (mesh.corner(t, 0).y != 0 || mesh.corner(t, 1).y != 0 || mesh.corner(t, 2).y != 0)
        continue;
      area += mesh.area(t);
      ++triangles;
    }
    return area;
  };
  int64_t publishedTriangles = 0, handCutTriangles = 0;
  const double whole = floorArea(published, publishedTriangles);
  const double cut = floorArea(handCut, handCutTriangles);
  EXPECT_EQ(publishedTriangles, 2);
  EXPECT_GT(handCutTriangles, 2);
  // The footprints (shoelace): 130,65 290,114 240,272 82,225 and 423,247 472,406 314,456 265,296.
  const double footprints = 0.5 * (130 * 114 - 290 * 65 + 290 * 272 - 240 * 114 + 240 * 225 -
                                   82 * 272 + 82 * 65 - 130 * 225) +
                            0.5 * (423 * 406 - 472 * 247 + 472 * 456 - 314 * 406 + 314 * 296 -
                                   265 * 456 + 265 * 247 - 423 * 296);
  EXPECT_NEAR(whole - cut, footprints, 1e-6 * whole);
  expectInputError([] { loadScene("builtin:cornell?cut_floor=2"); }, {"cut_floor"});
}

TEST(Builtin, CornellBoxGeometryMaterialsAndOrientation) {
  const Mesh mesh = loadScene("builtin:cornell");
  EXPECT_TRUE(mesh.warnings.empty());
  // The floor comes first, cut around the blocks' footprints into convex pieces (faces
  // 0 .. floorFaces − 1); then 9 ceiling cells, 3 walls, 2 × 5 block faces.
  int64_t floorFaces = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.labelNames.at(mesh.label[t]) == "floor")
      floorFaces = std::max(floorFaces, mesh.sourceFace[t] + 1);
  }
  EXPECT_EQ(floorFaces, 17);  // 9 slabs between the corners' z; 1, 2 or 3 pieces each
  EXPECT_EQ(mesh.sourceFace.back(), floorFaces + 21);
  const int64_t f0 = floorFaces - 1;  // face numbers below are those of a one-piece floor + f0
  // No floor under the blocks: the floor's area is the room's less the two footprints.
  double floorArea = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    if (mesh.sourceFace[t] < floorFaces) floorArea += mesh.area(t);
  auto shoelace = [](const std::vector<std::array<double, 2>>& p) {
    double twice = 0;
    for (size_t k = 0; k < p.size(); ++k) {
      const auto& a = p[k];
      const auto& b = p[(k + 1) % p.size()];
      twice += a[0] * b[1] - b[0] * a[1];
    }
    return std::abs(twice) / 2;
  };
  const double footprints = shoelace({{130, 65}, {290, 114}, {240, 272}, {82, 225}}) +
                            shoelace({{423, 247}, {472, 406}, {314, 456}, {265, 296}});
  EXPECT_NEAR(floorArea, 0.5 * (552.8 + 549.6) * 559.2 - footprints, 1e-6 * floorArea);
  // Floor ≈ ceiling ≈ walls ≈ 0.3 m², blocks ≈ 0.14 and 0.25 m²: about 1.9 m² in mm².
  EXPECT_GT(mesh.totalArea(), 1.8e6);
  EXPECT_LT(mesh.totalArea(), 2.0e6);

  const Rgb light = {std::numbers::pi * 17, std::numbers::pi * 12, std::numbers::pi * 4};
  double lightArea = 0;
  int emitting = 0;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const int64_t face = mesh.sourceFace[t];
    const Vec3 n = mesh.normal(t), c = mesh.centroid(t);
    if (mesh.emission[t][0] > 0) {
      ++emitting;
      lightArea += mesh.area(t);
      EXPECT_EQ(face, 5 + f0);
      EXPECT_EQ(mesh.emission[t], light);
      expectNear(n, {0, -1, 0});
    }
    if (face <= f0) {
      expectNear(n, {0, 1, 0});
    } else if (face >= 1 + f0 && face <= 9 + f0) {
      expectNear(n, {0, -1, 0});
    }
    if (face <= 12 + f0) {
      EXPECT_GT(dot(n, Vec3{278, 274, 280} - c), 0) << "room face " << face << " faces outward";
    } else {
      const Vec3 blockCentre = face <= 17 + f0 ? Vec3{185.5, 82.5, 169} : Vec3{368.5, 165, 351.25};
      EXPECT_GT(dot(n, c - blockCentre), 0) << "block face " << face << " faces inward";
    }
    if (face == 13 + f0 || face == 18 + f0) expectNear(n, {0, 1, 0});
  }
  EXPECT_EQ(emitting, 2);
  EXPECT_NEAR(lightArea, 130.0 * 105.0, 1e-9);
  // Red on the x ≈ 556 wall, green on x = 0.
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] == 11 + f0) {
      EXPECT_EQ(mesh.reflectance[t], (Rgb{0.14, 0.45, 0.091}));
    }
    if (mesh.sourceFace[t] == 12 + f0) {
      EXPECT_EQ(mesh.reflectance[t], (Rgb{0.63, 0.065, 0.05}));
    }
  }
  // The ceiling cells and the light form one conforming grid: 16 shared vertices.
  std::set<int64_t> ceiling;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.sourceFace[t] >= 1 + f0 && mesh.sourceFace[t] <= 9 + f0) {
      ceiling.insert(mesh.triangles[t].begin(), mesh.triangles[t].end());
    }
  }
  EXPECT_EQ(ceiling.size(), 16u);

  const Mesh brighter = loadScene("builtin:cornell?light=2.5");
  for (int64_t t = 0; t < brighter.triangleCount(); ++t) {
    if (brighter.sourceFace[t] == 5 + f0) {
      EXPECT_NEAR(brighter.emission[t][0], 2.5 * light[0], 1e-12);
    }
  }
}

TEST(Builtin, ScenesLabelTheirSurfaces) {
  const Mesh cornell = loadScene("builtin:cornell");
  ASSERT_TRUE(cornell.hasLabels());
  std::map<std::string, int> triangles;
  for (size_t t = 0; t < cornell.label.size(); ++t) {
    const std::string& name = cornell.labelNames.at(cornell.label[t]);
    ++triangles[name];
    EXPECT_EQ(cornell.emission[t][0] > 0, name == "light") << name;
  }
  EXPECT_EQ(triangles, (std::map<std::string, int>{{"floor", 34},
                                                   {"ceiling", 16},
                                                   {"light", 2},
                                                   {"back wall", 2},
                                                   {"red wall", 2},
                                                   {"green wall", 2},
                                                   {"short block", 10},
                                                   {"tall block", 10}}));
  for (const char* spec : {"builtin:box", "builtin:plates", "builtin:sphere?level=0"}) {
    const Mesh mesh = loadScene(spec);
    EXPECT_TRUE(mesh.hasLabels()) << spec;
  }
  EXPECT_EQ(loadScene("builtin:box").labelNames.size(), 6u);
}

TEST(Builtin, BoxIsClosedWithInwardNormals) {
  const Mesh mesh = loadScene("builtin:box?rho=0.8&e=2&size=3");
  EXPECT_EQ(mesh.triangleCount(), 12);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_TRUE(closedAndOriented(mesh));
  EXPECT_NEAR(signedVolume(mesh), -27, 1e-9);  // negative: normals point inward
  EXPECT_NEAR(mesh.totalArea(), 54, 1e-9);
  for (int64_t t = 0; t < 12; ++t) {
    EXPECT_GT(dot(mesh.normal(t), Vec3{1.5, 1.5, 1.5} - mesh.centroid(t)), 0);
    EXPECT_EQ(mesh.reflectance[t], (Rgb{0.8, 0.8, 0.8}));
    EXPECT_EQ(mesh.emission[t], (Rgb{2, 2, 2}));
    EXPECT_EQ(mesh.sourceFace[t], t / 2);
  }
  const Mesh defaults = loadScene("builtin:box");
  EXPECT_EQ(defaults.reflectance[0], (Rgb{0.5, 0.5, 0.5}));
  EXPECT_EQ(defaults.emission[0], (Rgb{1, 1, 1}));
  EXPECT_NEAR(defaults.totalArea(), 6, 1e-12);
}

TEST(Builtin, PlatesFaceEachOtherWithTheKnownViewFactor) {
  const Mesh mesh = loadScene("builtin:plates?e=3&rho=0.25");
  ASSERT_EQ(mesh.triangleCount(), 4);
  for (int64_t t = 0; t < 4; ++t) {
    const bool emitter = mesh.sourceFace[t] == 0;
    expectNear(mesh.normal(t), {0, 0, emitter ? 1.0 : -1.0});
    EXPECT_EQ(mesh.centroid(t).z, emitter ? 0 : 1);
    EXPECT_EQ(mesh.emission[t], (emitter ? Rgb{3, 3, 3} : Rgb{0, 0, 0}));
    EXPECT_EQ(mesh.reflectance[t], (emitter ? Rgb{0, 0, 0} : Rgb{0.25, 0.25, 0.25}));
  }
  EXPECT_NEAR(mesh.totalArea(), 2, 1e-12);
  // Midpoint quadrature of F = ∫∫ cosθ₁ cosθ₂ / (π r²) over the two unit squares.
  const int n = 20;
  double f = 0;
  for (int i = 0; i < n * n; ++i) {
    for (int j = 0; j < n * n; ++j) {
      const double dx = ((i % n) - (j % n)) / double(n), dy = ((i / n) - (j / n)) / double(n);
      const double r2 = dx * dx + dy * dy + 1;
      f += 1 / (std::numbers::pi * r2 * r2);
    }
  }
  f /= double(n) * n * n * n;
  EXPECT_NEAR(f, 0.19982, 1e-3);

  const Mesh far = loadScene("builtin:plates?distance=2.5&rho_emitter=0.5");
  EXPECT_EQ(far.centroid(3).z, 2.5);
  EXPECT_EQ(far.reflectance[0], (Rgb{0.5, 0.5, 0.5}));
}

TEST(Builtin, PlatesTakeSizesAndAPerpendicularVariant) {
  const Mesh sized = loadScene("builtin:plates?width=2&height=0.5&distance=3");
  EXPECT_NEAR(sized.totalArea(), 2, 1e-12);
  EXPECT_EQ(sized.centroid(3).z, 3);
  const Mesh bent = loadScene("builtin:plates?angle=90&width=2&height=0.5");
  ASSERT_EQ(bent.triangleCount(), 4);
  EXPECT_EQ(bent.vertices.size(), 6u);  // the common edge is shared
  for (int64_t t = 0; t < 4; ++t) {
    const bool emitter = bent.sourceFace[t] == 0;
    expectNear(bent.normal(t), emitter ? Vec3{0, 0, 1} : Vec3{0, 1, 0});
    EXPECT_NEAR(bent.area(t), 0.5, 1e-12);
    if (!emitter) {
      EXPECT_EQ(bent.centroid(t).y, 0);
      EXPECT_GT(bent.centroid(t).z, 0);
    }
  }
  expectInputError([] { loadScene("builtin:plates?angle=45"); }, {"'angle' must be 0 or 90"});
  expectInputError([] { loadScene("builtin:plates?angle=90&distance=2"); },
                   {"'distance'", "angle=0"});
  expectInputError([] { loadScene("builtin:plates?width=0"); }, {"'width'", "out of range"});
}

/// The triangles of `mesh` labelled `name`.
std::vector<int64_t> labelled(const Mesh& mesh, const std::string& name) {
  std::vector<int64_t> out;
  const auto it = std::find(mesh.labelNames.begin(), mesh.labelNames.end(), name);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (it != mesh.labelNames.end() && mesh.label[t] == it - mesh.labelNames.begin()) {
      out.push_back(t);
    }
  }
  return out;
}

TEST(Builtin, RoomsHaveTheRequestedSizeAndFaceTheirLitSides) {
  for (int64_t target : {1000, 10000, 100000}) {
    SCOPED_TRACE(target);
    const Mesh mesh = loadScene("builtin:rooms?patches=" + std::to_string(target));
    EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
    EXPECT_GE(mesh.triangleCount(), target - target / 5);
    EXPECT_LE(mesh.triangleCount(), target + target / 5);
    ASSERT_TRUE(mesh.hasLabels());

    // Every room has a light in its ceiling, facing down.
    const auto lights = labelled(mesh, "light");
    ASSERT_FALSE(lights.empty());
    for (int64_t t : lights) {
      EXPECT_GT(mesh.emission[t][0], 0);
      expectNear(mesh.normal(t), {0, -1, 0});
    }
    for (int64_t t : labelled(mesh, "floor")) expectNear(mesh.normal(t), {0, 1, 0});
    for (int64_t t : labelled(mesh, "ceiling")) expectNear(mesh.normal(t), {0, -1, 0});
    // Walls face the centre of their room (rooms are 4 m squares from the origin).
    for (int64_t t : labelled(mesh, "wall")) {
      const Vec3 c = mesh.centroid(t);
      const Vec3 centre = {(std::floor(c.x / 4) + 0.5) * 4, c.y, (std::floor(c.z / 4) + 0.5) * 4};
      EXPECT_GT(dot(mesh.normal(t), centre - c), 0) << "wall triangle " << t;
    }
    // Furniture faces out, away from the centre of its box: 5 consecutive source faces, the
    // top first.
    for (const char* piece : {"table", "shelf"}) {
      const auto triangles = labelled(mesh, piece);
      ASSERT_FALSE(triangles.empty()) << piece;
      std::map<int64_t, std::pair<Vec3, Vec3>> boxes;  // first source face → bounds
      int64_t first = -1;
      std::map<int64_t, int64_t> boxOf;
      for (int64_t t : triangles) {
        const int64_t f = mesh.sourceFace[t];
        if (first < 0 || f >= first + 5) first = f;
        boxOf[t] = first;
        auto& [lo, hi] =
            boxes.try_emplace(first, Vec3{1e9, 1e9, 1e9}, Vec3{-1e9, -1e9, -1e9}).first->second;
        for (int k = 0; k < 3; ++k) {
          for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], mesh.corner(t, k)[a]);
            hi[a] = std::max(hi[a], mesh.corner(t, k)[a]);
          }
        }
      }
      for (int64_t t : triangles) {
        const auto& [lo, hi] = boxes[boxOf[t]];
        EXPECT_GT(dot(mesh.normal(t), mesh.centroid(t) - 0.5 * (lo + hi)), 0) << piece << " " << t;
      }
    }
    // Closed apart from the furniture's open bottoms: every edge is used by two triangles in
    // opposite directions, except rims lying on the floor.
    std::map<std::pair<int64_t, int64_t>, int> directed;
    for (const Triangle& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
      ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " repeated";
      if (!directed.contains({edge.second, edge.first})) {
        ASSERT_EQ(mesh.vertices[edge.first].y, 0);
        ASSERT_EQ(mesh.vertices[edge.second].y, 0);
      }
    }
  }
  // About one room per 2000 triangles in a near-square plan (one light each); the same scene
  // for the same seed, another for another.
  auto rooms = [](const Mesh& mesh) {
    std::set<int64_t> faces;
    for (int64_t t : labelled(mesh, "light")) faces.insert(mesh.sourceFace[t]);
    return faces.size();
  };
  EXPECT_EQ(rooms(loadScene("builtin:rooms?patches=1000")), 1u);
  const Mesh a = loadScene("builtin:rooms?patches=20000&seed=3");
  EXPECT_EQ(rooms(a), 9u);
  EXPECT_EQ(a.vertices, loadScene("builtin:rooms?patches=20000&seed=3").vertices);
  EXPECT_NE(a.vertices, loadScene("builtin:rooms?patches=20000&seed=4").vertices);
  expectInputError([] { loadScene("builtin:rooms?patches=999"); }, {"'patches'", "out of range"});
  expectInputError([] { loadScene("builtin:rooms?patches=10000001"); }, {"out of range"});
  expectInputError([] { loadScene("builtin:rooms?patches=1500.5"); }, {"integer"});
}

/// A building's bounds, from its triangles (label k).
struct Bounds {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(Vec3 p) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
};

std::vector<Bounds> buildingBounds(const Mesh& mesh) {
  std::vector<Bounds> bounds(mesh.labelNames.size());
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) bounds[mesh.label[t]].add(mesh.corner(t, k));
  }
  return bounds;
}

TEST(Builtin, CityFacesOutOnAGroundWithHolesUnderTheBuildings) {
  const Mesh mesh = loadScene("builtin:city");
  EXPECT_TRUE(mesh.warnings.empty());
  ASSERT_TRUE(mesh.hasLabels());
  ASSERT_EQ(mesh.labelNames.size(), 65u);
  EXPECT_EQ(mesh.labelNames[0], "ground");
  EXPECT_EQ(mesh.labelNames[64], "building 64");
  EXPECT_EQ(mesh.lengthUnit, "m");
  // The defaults aim at about 5,000 triangles; the count follows the area over element².
  EXPECT_GE(mesh.triangleCount(), 4500);
  EXPECT_LE(mesh.triangleCount(), 5500);
  const double cells = mesh.totalArea() / (6.5 * 6.5);
  EXPECT_GT(mesh.triangleCount(), 2 * cells * 0.8);
  EXPECT_LT(mesh.triangleCount(), 2 * cells * 1.25);

  const auto bounds = buildingBounds(mesh);
  // The ground: 8 lots of 16 + 8 m and half a street around, 200 m square, at y = 0.
  EXPECT_EQ(bounds[0].lo, (Vec3{0, 0, 0}));
  EXPECT_EQ(bounds[0].hi, (Vec3{200, 0, 200}));
  double groundArea = 0, footprints = 0;
  for (int64_t t : labelled(mesh, "ground")) {
    expectNear(mesh.normal(t), {0, 1, 0});
    EXPECT_EQ(mesh.sourceFace[t], 0);
    groundArea += mesh.area(t);
  }
  for (size_t k = 1; k < bounds.size(); ++k) {
    const Bounds& b = bounds[k];
    EXPECT_EQ(b.lo.y, 0);
    EXPECT_GE(b.hi.y, 6);
    EXPECT_LE(b.hi.y, 30);
    for (int a : {0, 2}) {
      EXPECT_GE(b.hi[a] - b.lo[a], 10);
      EXPECT_LE(b.hi[a] - b.lo[a], 16);
    }
    footprints += (b.hi.x - b.lo.x) * (b.hi.z - b.lo.z);
    // Streets at least 8 m wide.
    for (size_t l = 1; l < k; ++l) {
      const Bounds& o = bounds[l];
      const double gap = std::max(std::max(o.lo.x - b.hi.x, b.lo.x - o.hi.x),
                                  std::max(o.lo.z - b.hi.z, b.lo.z - o.hi.z));
      EXPECT_GE(gap, 8 - 1e-9) << "buildings " << k << " and " << l;
    }
  }
  EXPECT_NEAR(groundArea, 200.0 * 200.0 - footprints, 1e-6);

  // Roofs face up at the top, walls away from their building's axis; source faces 5k − 4 (the
  // roof) to 5k (the walls) for building k. Nothing below the ground or inside a building.
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 c = mesh.centroid(t);
    for (int k = 0; k < 3; ++k) EXPECT_GE(mesh.corner(t, k).y, 0);
    for (size_t k = 1; k < bounds.size(); ++k) {
      const Bounds& b = bounds[k];
      const bool inside = c.x > b.lo.x + 1e-9 && c.x < b.hi.x - 1e-9 && c.z > b.lo.z + 1e-9 &&
                          c.z < b.hi.z - 1e-9 && c.y < b.hi.y - 1e-9;
      ASSERT_FALSE(inside) << "triangle " << t << " inside building " << k;
    }
    const int32_t k = mesh.label[t];
    if (k == 0) continue;
    const Bounds& b = bounds[k];
    const int64_t face = mesh.sourceFace[t] - (5 * int64_t{k} - 4);
    ASSERT_GE(face, 0);
    ASSERT_LT(face, 5);
    if (face == 0) {
      expectNear(mesh.normal(t), {0, 1, 0});
      for (int v = 0; v < 3; ++v) EXPECT_EQ(mesh.corner(t, v).y, b.hi.y);
    } else {
      const Vec3 axis = {(b.lo.x + b.hi.x) / 2, c.y, (b.lo.z + b.hi.z) / 2};
      EXPECT_NEAR(mesh.normal(t).y, 0, 1e-12);
      EXPECT_GT(dot(mesh.normal(t), c - axis), 0) << "wall triangle " << t;
    }
  }

  // Conforming where buildings meet the ground and roofs the walls: every edge of a building
  // is used again in the opposite direction (by the building or the ground beside it).
  std::set<std::pair<int64_t, int64_t>> directed;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(directed.insert({t[k], t[(k + 1) % 3]}).second) << "edge repeated";
    }
  }
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.label[t] == 0) continue;
    const Triangle& v = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(directed.contains({v[(k + 1) % 3], v[k]})) << "open edge of triangle " << t;
    }
  }
}

TEST(Builtin, CityElementSizeSeedAndRefusals) {
  // ~30,000 triangles at element = 2.6 m (the benchmark's larger case), 4× the cells at half
  // the element size.
  const Mesh fine = loadScene("builtin:city?element=2.6");
  EXPECT_GE(fine.triangleCount(), 27000);
  EXPECT_LE(fine.triangleCount(), 33000);
  const Mesh small = loadScene("builtin:city?buildings=2&element=4&seed=3");
  const Mesh half = loadScene("builtin:city?buildings=2&element=2&seed=3");
  EXPECT_NEAR(double(half.triangleCount()) / small.triangleCount(), 4, 0.6);
  EXPECT_EQ(small.labelNames.size(), 5u);
  EXPECT_EQ(small.vertices, loadScene("builtin:city?buildings=2&element=4&seed=3").vertices);
  EXPECT_EQ(small.triangles, loadScene("builtin:city?buildings=2&element=4&seed=3").triangles);
  EXPECT_NE(small.vertices, loadScene("builtin:city?buildings=2&element=4&seed=4").vertices);
  // Materials: ρ everywhere, the ground emits e_ground, the buildings e_building.
  const Mesh lit = loadScene("builtin:city?buildings=1&rho=0.6&e_ground=2&e_building=0.5");
  for (int64_t t = 0; t < lit.triangleCount(); ++t) {
    EXPECT_EQ(lit.reflectance[t], (Rgb{0.6, 0.6, 0.6}));
    EXPECT_EQ(lit.emission[t][0], lit.label[t] == 0 ? 2 : 0.5);
  }
  // Equal bounds give equal buildings.
  const Mesh same = loadScene(
      "builtin:city?buildings=3&footprint_min=12&footprint_max=12&height_min=9&height_max=9");
  const auto bounds = buildingBounds(same);
  for (size_t k = 1; k < bounds.size(); ++k) {
    EXPECT_EQ(bounds[k].hi.y, 9);
    EXPECT_DOUBLE_EQ(bounds[k].hi.x - bounds[k].lo.x, 12);
  }

  expectInputError([] { loadScene("builtin:city?footprint_min=20"); },
                   {"builtin:city", "'footprint_min' exceeds 'footprint_max'"});
  expectInputError([] { loadScene("builtin:city?height_max=5"); },
                   {"'height_min' exceeds 'height_max'"});
  expectInputError([] { loadScene("builtin:city?element=0"); }, {"'element'", "out of range"});
  expectInputError([] { loadScene("builtin:city?element=0.001"); }, {"'element'", "triangles"});
  // (so small that the cells along an edge overflowed int64 and came back as one)
  expectInputError([] { loadScene("builtin:city?element=1e-30"); }, {"'element'", "triangles"});
  expectInputError([] { loadScene("builtin:city?buildings=0"); }, {"'buildings'", "out of range"});
  expectInputError([] { loadScene("builtin:city?buildings=2.5"); }, {"integer"});
  expectInputError([] { loadScene("builtin:city?street=-1"); }, {"'street'", "out of range"});
  expectInputError([] { loadScene("builtin:city?rho=1.5"); }, {"'rho'", "out of range"});
  expectInputError([] { loadScene("builtin:city?height=3"); }, {"unknown parameter 'height'"});
}

TEST(Builtin, SphereIsAClosedInwardEnclosure) {
  const Mesh mesh = loadScene("builtin:sphere?level=3&radius=2&rho=0.999");
  EXPECT_EQ(mesh.triangleCount(), 20 * 64);
  EXPECT_TRUE(closedAndOriented(mesh));
  EXPECT_LT(signedVolume(mesh), 0);
  EXPECT_NEAR(-signedVolume(mesh), 4.0 / 3.0 * std::numbers::pi * 8, 0.7);
  EXPECT_EQ(mesh.reflectance[0], (Rgb{0.999, 0.999, 0.999}));
}

TEST(Builtin, SphereCapLimitsEmissionToTheTopCap) {
  // A spherical cap z > c·r has the area fraction (1 − c)/2: a quarter for c = 0.5, up to
  // faceting (which triangles' centroids fall above the plane) at level 3.
  const Mesh capped = loadScene("builtin:sphere?level=3&radius=2&e=3&cap=0.5");
  double emitting = 0;
  for (int64_t t = 0; t < capped.triangleCount(); ++t) {
    const bool above = capped.centroid(t).z > 0.5 * 2;
    EXPECT_EQ(capped.emission[t], (above ? Rgb{3, 3, 3} : Rgb{0, 0, 0})) << t;
    if (above) emitting += capped.area(t);
  }
  EXPECT_NEAR(emitting / capped.totalArea(), 0.25, 0.005);
  EXPECT_GT(emitting, 0);

  // cap = 1: nothing emits; cap = −1 (the default): the old scene, every triangle emitting.
  const Mesh none = loadScene("builtin:sphere?level=2&cap=1");
  for (const Rgb& e : none.emission) EXPECT_EQ(e, (Rgb{0, 0, 0}));
  const Mesh all = loadScene("builtin:sphere?level=3&radius=2&e=3&cap=-1");
  const Mesh old = loadScene("builtin:sphere?level=3&radius=2&e=3");
  EXPECT_EQ(all.vertices, old.vertices);
  EXPECT_EQ(all.triangles, old.triangles);
  EXPECT_EQ(all.emission, old.emission);
  EXPECT_EQ(all.reflectance, old.reflectance);
  for (const Rgb& e : all.emission) EXPECT_EQ(e, (Rgb{3, 3, 3}));
  // The geometry does not depend on the cap.
  EXPECT_EQ(capped.vertices, old.vertices);
  EXPECT_EQ(capped.triangles, old.triangles);

  expectInputError([] { loadScene("builtin:sphere?cap=1.5"); }, {"'cap'", "out of range"});
  expectInputError([] { loadScene("builtin:sphere?cap=-2"); }, {"'cap'", "out of range"});
}

TEST(Builtin, BadSpecsAreInputErrors) {
  expectInputError([] { loadScene("builtin:box?foo=1"); },
                   {"builtin:box?foo=1: unknown parameter 'foo' (known: rho, e, size)"});
  expectInputError([] { loadScene("builtin:nothing"); },
                   {"builtin:nothing", "unknown built-in scene 'nothing'", "cornell"});
  expectInputError([] { loadScene("builtin:box?rho=abc"); }, {"'rho'", "not a finite number"});
  expectInputError([] { loadScene("builtin:box?rho=1.5"); }, {"'rho'", "out of range"});
  expectInputError([] { loadScene("builtin:box?e=-1"); }, {"'e'", "out of range"});
  expectInputError([] { loadScene("builtin:box?size=0"); }, {"'size'", "out of range"});
  expectInputError([] { loadScene("builtin:box?rho=nan"); }, {"'rho'"});
  expectInputError([] { loadScene("builtin:box?rho"); }, {"malformed parameter 'rho'"});
  expectInputError([] { loadScene("builtin:box?rho=0.1&rho=0.2"); }, {"given twice"});
  expectInputError([] { loadScene("builtin:cornell?rho=0.1"); },
                   {"(known: light, scale, cut_floor)"});
  expectInputError([] { loadScene("builtin:sphere?level=1.5"); }, {"integer"});
  expectInputError([] { loadScene("builtin:"); }, {"unknown built-in scene ''"});
}

}  // namespace
}  // namespace radiosity
