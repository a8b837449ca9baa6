// The exact answers of the accuracy study (jobs/study/exact_answers.cpp): the closed enclosures'
// formulas, the plates' per-patch view factors against the closed-form plate-to-plate ones, and
// the triangle quadrature behind them.
#include "jobs/study/exact_answers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "tests/analytic_view_factors.h"

namespace radiosity::jobs {
namespace {

/// Splits every triangle into four at its edge midpoints, `levels` times, keeping each
/// triangle's source face, ρ and E (as the solve's refinement does; vertices are not welded).
Mesh refine(Mesh mesh, int levels) {
  for (int level = 0; level < levels; ++level) {
    Mesh finer;
    finer.vertices = mesh.vertices;
    for (int64_t t = 0; t < mesh.triangleCount(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      auto add = [&](Vec3 p) {
        finer.vertices.push_back(p);
        return static_cast<int64_t>(finer.vertices.size()) - 1;
      };
      const int64_t ab = add(0.5 * (mesh.corner(t, 0) + mesh.corner(t, 1)));
      const int64_t bc = add(0.5 * (mesh.corner(t, 1) + mesh.corner(t, 2)));
      const int64_t ca = add(0.5 * (mesh.corner(t, 2) + mesh.corner(t, 0)));
      for (const Triangle& child : {Triangle{tri[0], ab, ca}, Triangle{ab, tri[1], bc},
                                    Triangle{ca, bc, tri[2]}, Triangle{ab, bc, ca}}) {
        finer.triangles.push_back(child);
        finer.sourceFace.push_back(mesh.sourceFace[t]);
        finer.reflectance.push_back(mesh.reflectance[t]);
        finer.emission.push_back(mesh.emission[t]);
      }
    }
    mesh = std::move(finer);
  }
  return mesh;
}

void expectRgbNear(const Rgb& actual, const Rgb& expected, double tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], tolerance) << "channel " << c;
}

TEST(ExactAnswers, ClosedBoxIsEOverOneMinusRho) {
  for (int levels : {0, 2}) {
    const Mesh patches = refine(loadScene("builtin:box?rho=0.9&e=2"), levels);
    const auto answer = exactAnswer("builtin:box?rho=0.9&e=2", patches);
    ASSERT_TRUE(answer);
    ASSERT_EQ(answer->radiosity.size(), patches.triangles.size());
    ASSERT_EQ(answer->irradiance.size(), patches.triangles.size());
    for (size_t t = 0; t < patches.triangles.size(); ++t) {
      expectRgbNear(answer->radiosity[t], {20, 20, 20}, 1e-12);
      // H = Σ_j F_ij B_j = B as the rows of F sum to 1 and B is uniform; B = E + ρH.
      expectRgbNear(answer->irradiance[t], answer->radiosity[t], 0);
      const Rgb& h = answer->irradiance[t];
      expectRgbNear(answer->radiosity[t], {2 + 0.9 * h[0], 2 + 0.9 * h[1], 2 + 0.9 * h[2]}, 1e-12);
    }
    EXPECT_NE(answer->how.find("box"), std::string::npos);
  }
  // ρ = 1: no finite answer.
  EXPECT_FALSE(exactAnswer("builtin:box?rho=1", loadScene("builtin:box?rho=1")));
}

TEST(ExactAnswers, SphereUsesTheAreaWeightedMeanEmission) {
  const std::string spec = "builtin:sphere?rho=0.7&cap=0.5&level=3";
  const Mesh patches = loadScene(spec);
  const auto answer = exactAnswer(spec, patches);
  ASSERT_TRUE(answer);
  EXPECT_NE(answer->how.find("faceting"), std::string::npos);
  const double total = patches.totalArea();
  double emitting = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    emitting += patches.area(t) * patches.emission[t][0];
  }
  const double eBar = emitting / total;
  EXPECT_NEAR(eBar, 0.25, 0.005);  // the cap's share of the area (e = 1)
  // The answer solves B = E + ρ F B with F_ij = A_j / A exactly.
  Rgb fb = {0, 0, 0};
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    for (int c = 0; c < 3; ++c) fb[c] += patches.area(t) / total * answer->radiosity[t][c];
  }
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const double h = eBar / 0.3;
    expectRgbNear(answer->irradiance[t], {h, h, h}, 1e-12);
    expectRgbNear(answer->irradiance[t], fb, 1e-12);
    const double e = patches.emission[t][0];
    expectRgbNear(answer->radiosity[t], {e + 0.7 * h, e + 0.7 * h, e + 0.7 * h}, 1e-12);
  }

  // Every triangle emitting: the enclosure's B = E/(1 − ρ), as for the box.
  const auto all = exactAnswer("builtin:sphere?rho=0.5&e=2&level=2",
                               refine(loadScene("builtin:sphere?rho=0.5&e=2&level=2"), 1));
  ASSERT_TRUE(all);
  for (size_t t = 0; t < all->radiosity.size(); ++t) {
    expectRgbNear(all->radiosity[t], {4, 4, 4}, 1e-12);
    expectRgbNear(all->irradiance[t], {4, 4, 4}, 1e-12);
  }
}

struct PlatesCase {
  std::string spec;
  double expected;  ///< the closed-form receiver → emitter view factor
};

TEST(ExactAnswers, PlatesPatchViewFactorsAverageToThePlateToPlateOne) {
  using radiosity::testing::parallelRectangles;
  using radiosity::testing::perpendicularRectangles;
  EXPECT_NEAR(parallelRectangles(1, 1, 1), 0.19982, 1e-5);
  EXPECT_NEAR(perpendicularRectangles(1, 1, 1), 0.20004, 1e-5);
  const std::vector<PlatesCase> cases = {
      {"builtin:plates", parallelRectangles(1, 1, 1)},
      {"builtin:plates?width=1&height=1&distance=1&e=3", parallelRectangles(1, 1, 1)},
      {"builtin:plates?width=1&height=2&distance=1", parallelRectangles(1, 2, 1)},
      {"builtin:plates?width=2&height=0.5&distance=0.1", parallelRectangles(2, 0.5, 0.1)},
      {"builtin:plates?angle=90", perpendicularRectangles(1, 1, 1)},
      // the receiver is width × height standing on the common edge (width), the emitter
      // reaches height away from it
      {"builtin:plates?angle=90&width=2&height=0.5", perpendicularRectangles(2, 0.5, 0.5)},
      {"builtin:plates?angle=90&width=1&height=3", perpendicularRectangles(1, 3, 3)},
  };
  for (const PlatesCase& c : cases) {
    for (int levels : {0, 1, 3}) {
      SCOPED_TRACE(c.spec + " refined " + std::to_string(levels) + " times");
      const Mesh scene = loadScene(c.spec);
      const Mesh patches = refine(scene, levels);
      const auto answer = exactAnswer(c.spec, patches);
      ASSERT_TRUE(answer);
      const double e = scene.emission[0][0];  // triangle 0 is the emitter's
      double weighted = 0, area = 0;
      for (int64_t t = 0; t < patches.triangleCount(); ++t) {
        expectRgbNear(answer->radiosity[t], patches.emission[t], 0);  // ρ = 0: B = E
        if (patches.sourceFace[t] == 0) {
          expectRgbNear(answer->irradiance[t], {0, 0, 0}, 0);
          continue;
        }
        const double f = answer->irradiance[t][0] / e;
        EXPECT_GT(f, 0) << t;
        EXPECT_LT(f, 1) << t;
        EXPECT_EQ(answer->irradiance[t][1], answer->irradiance[t][0]);
        EXPECT_EQ(answer->irradiance[t][2], answer->irradiance[t][0]);
        weighted += patches.area(t) * f;
        area += patches.area(t);
      }
      EXPECT_NEAR(weighted / area, c.expected, 1e-6);
    }
  }
}

TEST(ExactAnswers, PlatesWithAReflectingEmitterHaveNoClosedForm) {
  for (const char* spec : {"builtin:plates?rho_emitter=0.1", "builtin:plates?rho=0.5&rho_emitter=1",
                           "builtin:plates?angle=90&rho_emitter=0.3"}) {
    EXPECT_FALSE(exactAnswer(spec, loadScene(spec))) << spec;
  }
}

// A reflecting receiver under a black emitter: its light never comes back, so B = E + ρ H there.
TEST(ExactAnswers, PlatesWithAReflectingReceiverAddItsReflection) {
  for (const char* spec : {"builtin:plates?rho=0.5", "builtin:plates?angle=90&rho=1"}) {
    const Mesh patches = loadScene(spec);
    const std::optional<ExactAnswer> answer = exactAnswer(spec, patches);
    ASSERT_TRUE(answer) << spec;
    for (int64_t t = 0; t < patches.triangleCount(); ++t) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_DOUBLE_EQ(
            answer->radiosity[t][c],
            patches.emission[t][c] + (patches.sourceFace[t] == 0
                                          ? 0.0
                                          : patches.reflectance[t][c] * answer->irradiance[t][c]))
            << spec << " patch " << t;
      }
    }
  }
}

TEST(ExactAnswers, OtherScenesHaveNone) {
  const Mesh box = loadScene("builtin:box");
  for (const char* spec :
       {"builtin:cornell", "builtin:rooms?patches=1000", "scene.obj", "box", ""}) {
    EXPECT_FALSE(exactAnswer(spec, box)) << spec;
  }
  // Read as loadScene() reads them (io's one parser): unknown scenes and bad values are refused.
  EXPECT_THROW(exactAnswer("builtin:boxes", box), InputError);
  EXPECT_THROW(exactAnswer("builtin:box?rho=abc", box), InputError);
  EXPECT_THROW(exactAnswer("builtin:plates?widht=2", box), InputError);
}

TEST(MeanOverTriangle, IsExactForDegreeEightAndAdaptiveOtherwise) {
  const Vec3 a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0};
  // ∫_T x^i y^j = i! j! / (i + j + 2)! over the unit right triangle (area 1/2).
  EXPECT_NEAR(meanOverTriangle([](const Vec3& p) { return std::pow(p.x, 8); }, a, b, c, 0, 0),
              2.0 / 90, 1e-14);
  EXPECT_NEAR(meanOverTriangle([](const Vec3& p) { return std::pow(p.x * p.y, 4); }, a, b, c, 0, 0),
              2.0 / 6300, 1e-14);
  EXPECT_NEAR(meanOverTriangle([](const Vec3& p) { return std::pow(p.y, 3) * std::pow(p.x, 5); }, a,
                               b, c, 0, 0),
              2.0 * 6 * 120 / 3628800, 1e-14);
  EXPECT_NEAR(meanOverTriangle([](const Vec3&) { return 1.0; }, a, b, c, 0, 0), 1, 1e-14);
  // exp(x + y) over T: ∫_0^1 s e^s ds = 1, mean 2. The rule alone is off; adaptivity fixes it.
  const auto exp = [](const Vec3& p) { return std::exp(8 * (p.x + p.y)); };
  const double exact = 2 * (7 * std::exp(8.0) + 1) / 64;  // ∫_0^1 s e^{8s} ds = (7e^8 + 1)/64
  EXPECT_GT(std::abs(meanOverTriangle(exp, a, b, c, 0, 0) - exact), 1e-9 * exact);
  EXPECT_NEAR(meanOverTriangle(exp, a, b, c, 1e-10 * exact), exact, 1e-9 * exact);
  EXPECT_NEAR(meanOverTriangle([](const Vec3& p) { return std::exp(p.x + p.y); }, a, b, c, 1e-12),
              2, 1e-11);
  // The polar angle, discontinuous at a corner as the view factor to a perpendicular
  // rectangle is at the ends of the common edge: over (0,0), (1,0), (1,1) its mean is
  // 2 ∫_0^{π/4} θ / (2 cos²θ) dθ = π/4 − ln(2)/2. Refined towards the corner.
  const double angle = meanOverTriangle([](const Vec3& p) { return std::atan2(p.y, p.x); },
                                        {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, 1e-10);
  EXPECT_NEAR(angle, std::numbers::pi / 4 - std::log(2.0) / 2, 1e-9);
}

}  // namespace
}  // namespace radiosity::jobs
