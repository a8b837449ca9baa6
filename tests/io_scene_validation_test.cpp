// Validation of meshes from any source: what later stages cannot use is refused, and what counts
// as degenerate is relative to the scene's size.
#include <gtest/gtest.h>

#include <string>

#include "io/core/error.h"
#include "io/core/mesh.h"
#include "io/scene/scene.h"
#include "io/scene/scene_internal.h"
#include "scene_fixture.h"

namespace radiosity {
namespace {

using testing::expectInputError;

Mesh oneTriangle() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  mesh.sourceFace = {0};
  mesh.reflectance = {{0.5, 0.5, 0.5}};
  mesh.emission = {{0, 0, 0}};
  return mesh;
}

TEST(Validation, RefusesWhatLaterStagesCannotUse) {
  auto expectRefused = [](const std::function<void(Mesh&)>& spoil, const std::string& problem) {
    Mesh mesh = oneTriangle();
    spoil(mesh);
    expectInputError([&] { detail::validateScene(mesh, "src"); }, {"src", problem});
  };
  expectRefused([](Mesh& m) { m.reflectance[0][1] = 1.0000001; }, "reflectance");
  expectRefused([](Mesh& m) { m.reflectance[0][2] = -0.1; }, "reflectance");
  expectRefused([](Mesh& m) { m.reflectance[0][0] = NAN; }, "reflectance");
  expectRefused([](Mesh& m) { m.emission[0][0] = -1; }, "emission");
  expectRefused([](Mesh& m) { m.emission[0][2] = INFINITY; }, "emission");
  expectRefused([](Mesh& m) { m.vertices[1].x = NAN; }, "vertex 2");
  expectRefused([](Mesh& m) { m.vertices[2].y = -INFINITY; }, "vertex 3");
  expectRefused([](Mesh& m) { m.vertices[0].z = 1e31; }, "vertex 1");
  expectRefused([](Mesh& m) { m.triangles[0][2] = 3; }, "vertex index 3");
  expectRefused([](Mesh& m) { m.triangles[0][0] = -1; }, "vertex index -1");
  Mesh fine = oneTriangle();
  fine.vertices = {{-1e30, 0, 0}, {1e30, 0, 0}, {0, 1e30, 0}};  // the largest magnitude allowed
  fine.reflectance[0] = {0, 1, 0.5};
  EXPECT_NO_THROW(detail::validateScene(fine, "src"));
}

TEST(Validation, DegeneracyIsRelativeToTheSceneSize) {
  Mesh big = oneTriangle();
  for (Vec3& v : big.vertices) v = 1e6 * v;  // area 5e11, not degenerate at any scale
  big.vertices.push_back({1e6, 1e6, 0});
  big.vertices.push_back({1e6 + 1e-4, 1e6, 0});
  big.vertices.push_back({1e6, 1e6 + 1e-4, 0});  // area 5e-9 < 1e-12 × diag² = 2
  big.triangles.push_back({3, 4, 5});
  big.sourceFace.push_back(1);
  big.reflectance.push_back({0, 0, 0});
  big.emission.push_back({0, 0, 0});
  detail::validateScene(big, "big");
  EXPECT_EQ(big.triangleCount(), 1);
  EXPECT_EQ(big.warnings.size(), 1u);

  Mesh tiny = oneTriangle();
  for (Vec3& v : tiny.vertices) v = 1e-9 * v;  // tiny, but the whole scene: kept
  detail::validateScene(tiny, "tiny");
  EXPECT_EQ(tiny.triangleCount(), 1);
  EXPECT_TRUE(tiny.warnings.empty());
}

}  // namespace
}  // namespace radiosity
