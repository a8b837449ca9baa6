// Tests of core/corner_radiosity: the radiosity at a patch's corners that render/ smooths with
// (area-weighted, creases and changes of surface kept sharp) and the least-squares gradients the
// discretisation estimate fits. One process, no MPI.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/corner_radiosity.h"
#include "core/mesh.h"
#include "test_scenes.h"

namespace radiosity {
namespace {

// Two coplanar triangles of areas 1 and 3 sharing an edge, and a third standing at 90° on it.
TEST(VertexRadiosity, AreaWeightedAverageThatKeepsCreasesSharp) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {3, 3, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 4, 1}};
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  ASSERT_NEAR(area[0], 0.5, 1e-12);
  ASSERT_NEAR(area[1], 2.5, 1e-12);
  ASSERT_NEAR(dot(normal[0], normal[2]), 0, 1e-12);
  std::vector<Rgb> b = {{1, 2, 3}, {4, 5, 6}, {100, 100, 100}};
  CornerRadiosity corner = cornerRadiosity(mesh, normal, area, b, oneSurface(mesh));

  // Vertex 1 and 2 are shared by the coplanar pair: (0.5·B0 + 2.5·B1) / 3.
  for (int c = 0; c < 3; ++c) {
    double mean = (0.5 * b[0][c] + 2.5 * b[1][c]) / 3;
    EXPECT_NEAR(corner[0][1][c], mean, 1e-12);  // vertex 1, seen from patch 0
    EXPECT_NEAR(corner[0][2][c], mean, 1e-12);  // vertex 2
    EXPECT_NEAR(corner[1][0][c], mean, 1e-12);  // vertex 1, seen from patch 1
    EXPECT_NEAR(corner[1][2][c], mean, 1e-12);
    EXPECT_NEAR(corner[0][0][c], b[0][c], 1e-12);  // vertex 0: patch 2 is across the crease
    EXPECT_NEAR(corner[1][1][c], b[1][c], 1e-12);  // vertex 3: patch 1 alone
    // Patch 2 keeps its own value at every corner: its neighbours are all across the crease.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(corner[2][k][c], b[2][c], 1e-12);
  }
}

TEST(VertexRadiosity, DuplicatedVerticesAreWelded) {
  Mesh mesh;
  // The same two triangles as above, but each with its own copy of the shared vertices.
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {3, 3, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
  std::vector<double> area = {mesh.area(0), mesh.area(1)};
  std::vector<Rgb> b = {{1, 1, 1}, {4, 4, 4}};
  CornerRadiosity corner = cornerRadiosity(mesh, normal, area, b, oneSurface(mesh));
  EXPECT_NEAR(corner[0][1][0], (0.5 * 1 + 2.5 * 4) / 3, 1e-12);
  EXPECT_NEAR(corner[1][0][0], (0.5 * 1 + 2.5 * 4) / 3, 1e-12);
}

TEST(VertexRadiosity, NeighboursWithinThirtyDegreesAreAveraged) {
  // Two unit right triangles hinged on the edge (0,0,0)-(0,1,0), folded by 20° and by 40°.
  for (double fold : {20.0, 40.0}) {
    double a = fold * std::numbers::pi / 180;
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {std::cos(a), 0, std::sin(a)}};
    mesh.triangles = {{0, 1, 2}, {0, 3, 1}};
    std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
    ASSERT_NEAR(dot(normal[0], normal[1]), std::cos(a), 1e-12);
    std::vector<double> area = {mesh.area(0), mesh.area(1)};
    CornerRadiosity corner =
        cornerRadiosity(mesh, normal, area, {{{2, 2, 2}}, {{4, 4, 4}}}, oneSurface(mesh));
    EXPECT_NEAR(corner[0][0][0], fold < 30 ? 3 : 2, 1e-12) << fold;
  }
}

// A light in a ceiling opening (builtin:cornell's): the emitting triangle L shares each of its
// edges with a coplanar ceiling triangle (1, 2, 3) of the same reflectance. B jumps at those
// edges, so neither side may be averaged with the other.
//
//          2 ------- 3
//        / | \       |
//      /   |   \  1  |
//    /  2  |  L  \   |
//  4 ----- 0 ------- 1
//          |  3   /
//          |   /
//          | /
//          5
Mesh lightInCeiling() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 2, 4}, {0, 5, 1}};
  mesh.reflectance.assign(4, {0.7, 0.7, 0.7});
  mesh.emission = {{10, 8, 3}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  return mesh;
}

CornerRadiosity cornersOf(const Mesh& mesh, const std::vector<Rgb>& b, const SurfaceIds& surfaces) {
  std::vector<Vec3> normal;
  std::vector<double> area;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    area.push_back(mesh.area(t));
  }
  return cornerRadiosity(mesh, normal, area, b, surfaces);
}

TEST(VertexRadiosity, ALightNeverMixesWithTheCeilingAroundIt) {
  const Mesh mesh = lightInCeiling();
  for (int64_t t = 0; t < mesh.triangleCount(); ++t)
    ASSERT_NEAR(mesh.normal(t).z, 1, 1e-15);  // coplanar: only the material tells them apart
  const std::vector<Rgb> b = {{10.35, 8.3, 3.2}, {0.5, 0.4, 0.2}, {0.3, 0.3, 0.1}, {0.1, 0.2, 0.3}};
  const CornerRadiosity corner = cornersOf(mesh, b, materialSurfaces(mesh));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(corner[0][k], b[0]) << "light corner " << k;
  // Every ceiling triangle has area 1/2: each ceiling corner is the plain mean of the ceiling
  // triangles at that vertex, the light left out.
  auto mean = [&](std::vector<int> patches) {
    Rgb m{0, 0, 0};
    for (int s : patches)
      for (int c = 0; c < 3; ++c) m[c] += b[s][c] / static_cast<double>(patches.size());
    return m;
  };
  const std::array<Rgb, 6> atVertex = {mean({2, 3}), mean({1, 3}), mean({1, 2}),
                                       mean({1}),    mean({2}),    mean({3})};
  for (int64_t t = 1; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(corner[t][k][c], atVertex[mesh.triangles[t][k]][c], 1e-15)
            << "ceiling patch " << t << " corner " << k;
}

// Materials are compared by value: another name with the same ρ and E is the same surface, and
// a reflectance alone (a red patch on a white wall) splits one.
TEST(VertexRadiosity, MaterialsAreTheirReflectanceAndEmission) {
  Mesh mesh = lightInCeiling();
  mesh.emission[0] = {0, 0, 0};
  mesh.label = {0, 1, 1, 1};
  mesh.labelNames = {"paint", "ceiling"};
  EXPECT_EQ(materialSurfaces(mesh), (SurfaceIds{0, 0, 0, 0}));
  mesh.reflectance[0] = {0.7, 0.1, 0.1};
  const SurfaceIds red = materialSurfaces(mesh);
  EXPECT_NE(red[0], red[1]);
  EXPECT_EQ(red[1], red[2]);
  EXPECT_EQ(red[1], red[3]);
  const std::vector<Rgb> b(4, Rgb{1, 1, 1});
  std::vector<Rgb> lit = b;
  lit[0] = {5, 1, 1};
  EXPECT_EQ(cornersOf(mesh, lit, red)[1][0], (Rgb{1, 1, 1}));
  // Vertex 1, of patches 0, 1 and 3 (equal areas).
  EXPECT_NEAR(cornersOf(mesh, lit, oneSurface(mesh))[1][0][0], 7.0 / 3, 1e-15);
}

// What the mesh knows beyond materials (a contact line, patches hidden under an object) comes as
// surface ids of the caller's: patch 3, say hidden, is left out of its neighbours' corners.
TEST(VertexRadiosity, SurfaceIdsSplitWhatTheMeshKnows) {
  const Mesh mesh = lightInCeiling();
  const std::vector<Rgb> b = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {0, 0, 0}};
  const CornerRadiosity corner = cornersOf(mesh, b, SurfaceIds{0, 0, 0, 1});
  EXPECT_EQ(corner[0][0], (Rgb{2, 2, 2}));        // vertex 0: patches 0 and 2, not 3
  EXPECT_EQ(corner[0][1], (Rgb{1.5, 1.5, 1.5}));  // vertex 1: patches 0 and 1, not 3
  for (int k = 0; k < 3; ++k) EXPECT_EQ(corner[3][k], b[3]);
  EXPECT_THROW(cornersOf(mesh, b, SurfaceIds{0, 0}), std::invalid_argument);
}

TEST(VertexRadiosity, InterpolatesBarycentrically) {
  std::array<Rgb, 3> corner = {Rgb{1, 0, 0}, Rgb{0, 2, 0}, Rgb{0, 0, 4}};
  Rgb at = interpolate(corner, 0.25, 0.5);
  EXPECT_NEAR(at[0], 0.25, 1e-15);
  EXPECT_NEAR(at[1], 0.5, 1e-15);
  EXPECT_NEAR(at[2], 2, 1e-15);
}

// A linear field's patch means on a 6 × 6 grid of a plane, with a fold of 90° along one side (a
// wall standing on it): the least-squares gradient is the field's own on every patch, the ones
// along the fold and the grid's edge included (where corner averages halve the slope towards
// the edge), and nothing from the wall leaks in across the crease.
TEST(PatchGradients, ExactForALinearFieldUpToTheEdges) {
  Mesh mesh;
  const int n = 6;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.vertices.push_back({double(i), double(j), 0});
  auto at = [&](int i, int j) { return int64_t{j * (n + 1) + i}; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const auto floorPatches = mesh.triangleCount();
  const auto top = static_cast<int64_t>(mesh.vertices.size());
  mesh.vertices.push_back({0, 0, 1});
  mesh.vertices.push_back({double(n), 0, 1});
  mesh.triangles.push_back({at(0, 0), top, at(n, 0)});  // the wall along y = 0, facing +y
  std::vector<Vec3> normal;
  std::vector<Rgb> value;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    normal.push_back(mesh.normal(t));
    const Triangle& c = mesh.triangles[t];
    const Vec3 centroid =
        (1.0 / 3) * (mesh.vertices[c[0]] + mesh.vertices[c[1]] + mesh.vertices[c[2]]);
    // 2x + 3y + 1, and its negative, on the floor; a constant of 100 on the wall
    const double f = 2 * centroid.x + 3 * centroid.y + 1;
    value.push_back(t < floorPatches ? Rgb{f, -f, 0} : Rgb{100, 100, 100});
  }
  ASSERT_NEAR(normal.back().y, 1, 1e-15);
  const PatchGradients g = patchGradients(mesh, normal, value, oneSurface(mesh));
  for (int64_t t = 0; t < floorPatches; ++t) {
    EXPECT_NEAR(g[t][0].x, 2, 1e-12) << t;
    EXPECT_NEAR(g[t][0].y, 3, 1e-12) << t;
    EXPECT_NEAR(g[t][0].z, 0, 1e-12) << t;
    EXPECT_NEAR(g[t][1].y, -3, 1e-12) << t;
    EXPECT_NEAR(length(g[t][2]), 0, 1e-12) << t;
  }
  // The wall is alone in its surface: no direction to fit, no gradient.
  EXPECT_EQ(length(g.back()[0]), 0);
  // A rank fits only its own rows: each the same, bit for bit, as in the whole scene's fit; a
  // range beyond the patches is refused.
  const int64_t first = 5, last = 29;
  const PatchGradients part = patchGradients(mesh, normal, value, oneSurface(mesh), first, last);
  ASSERT_EQ(static_cast<int64_t>(part.size()), last - first);
  for (int64_t t = first; t < last; ++t)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(part[t - first][c].x, g[t][c].x) << t;
      EXPECT_EQ(part[t - first][c].y, g[t][c].y) << t;
      EXPECT_EQ(part[t - first][c].z, g[t][c].z) << t;
    }
  EXPECT_THROW(patchGradients(mesh, normal, value, oneSurface(mesh), 3, mesh.triangleCount() + 1),
               std::invalid_argument);
  // Without an array of normals the fit takes the mesh's (what the discretisation estimate does,
  // to hold no scene-wide array of them): the same gradients, bit for bit.
  const SurfaceIds surfaces = oneSurface(mesh);
  const GradientFit fromMesh(mesh, surfaces);
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::array<Vec3, 3> h = fromMesh(t, value);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(h[c].x, g[t][c].x) << t;
      EXPECT_EQ(h[c].y, g[t][c].y) << t;
      EXPECT_EQ(h[c].z, g[t][c].z) << t;
    }
  }
}

// A rank fits its own rows from its own values and its neighbours' alone: a fit of patches
// [first, last), given the values of those patches and of neighboursOutside(), equals the whole
// scene's fit bit for bit; the neighbours are exactly the patches outside sharing a corner's
// position, and a patch outside the range, or a value not held, is refused.
TEST(PatchGradients, AFitOfARangeNeedsOnlyItsNeighbours) {
  Mesh mesh;
  testing::addSubdividedQuad(mesh, {0, 0, 0}, {8, 0, 0}, {0, 5.6, 0}, 8, {0.5, 0.5, 0.5},
                             {0, 0, 0});
  std::vector<Rgb> value;
  for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
    const Triangle& c = mesh.triangles[t];
    const Vec3 centroid =
        (1.0 / 3) * (mesh.vertices[c[0]] + mesh.vertices[c[1]] + mesh.vertices[c[2]]);
    value.push_back({std::sin(centroid.x) * centroid.y, centroid.x * centroid.x, 1.0 / (1 + t)});
  }
  const SurfaceIds surfaces = oneSurface(mesh);
  const GradientFit whole(mesh, surfaces);
  const int64_t first = 37, last = 81;
  const GradientFit part(mesh, surfaces, first, last);
  const std::vector<int64_t> around = part.neighboursOutside(first, last);
  std::vector<int64_t> expected;
  for (int64_t s = 0; s < mesh.triangleCount(); ++s) {
    if (s >= first && s < last) continue;
    bool touches = false;
    for (int64_t t = first; t < last && !touches; ++t)
      for (int64_t a : mesh.triangles[s])
        for (int64_t b : mesh.triangles[t]) touches |= a == b;
    if (touches) expected.push_back(s);
  }
  EXPECT_EQ(around, expected);
  const std::vector<Rgb> block(value.begin() + first, value.begin() + last);
  std::vector<Rgb> aroundValues;
  for (int64_t s : around) aroundValues.push_back(value[s]);
  const PatchValues held(first, block, around, aroundValues);
  for (int64_t t = first; t < last; ++t) {
    const std::array<Vec3, 3> g = part(t, held), h = whole(t, value);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(g[c].x, h[c].x) << t;
      EXPECT_EQ(g[c].y, h[c].y) << t;
      EXPECT_EQ(g[c].z, h[c].z) << t;
    }
  }
  EXPECT_THROW(part(first - 1, held), std::out_of_range);
  const PatchValues lacking(first, block, {}, {});
  EXPECT_THROW(part(first, lacking), std::out_of_range);
  EXPECT_THROW(GradientFit(mesh, surfaces, 5, mesh.triangleCount() + 1), std::invalid_argument);
}

TEST(PatchGradients, KeepSurfacesApart) {
  // Two coplanar triangles of different surfaces: each alone, so no gradient across the edge.
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  const std::vector<Vec3> normal = {mesh.normal(0), mesh.normal(1)};
  const PatchGradients g =
      patchGradients(mesh, normal, {{{0, 0, 0}}, {{5, 5, 5}}}, SurfaceIds{0, 1});
  EXPECT_EQ(length(g[0][0]), 0);
  EXPECT_EQ(length(g[1][0]), 0);
  const PatchGradients joined = patchGradients(mesh, normal, {{{0, 0, 0}}, {{5, 5, 5}}}, {0, 0});
  EXPECT_GT(length(joined[0][0]), 0);
}

}  // namespace
}  // namespace radiosity
