// Exact rows stored once a pair (through reciprocity, F_ji = F_ij A_i / A_j) as users get them
// from `radiosity solve`: the default for exact rows on floats where nothing reads F's rows
// whole; the closed box's answer at ρ = 0.999, the same on any number of ranks, and as whole rows
// give it; the labelled walls' group factors; a stop and a restart on another rank count; and
// the options that keep rows whole.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "analytic_view_factors.h"
#include "end_to_end_fixture.h"
#include "io/store/result.h"

namespace radiosity {
namespace {

using testing::EndToEnd;
using testing::ProgramRun;

constexpr const char* kPairs = "rows = exact, each pair stored once";

TEST_F(EndToEnd, PairsOnceGiveTheClosedBoxsAnswerOnAnyRankCount) {
  // (--formfactor-precision single: floats below the default's 4,096 patches)
  const std::string options =
      " 'builtin:box?rho=0.999' --max-area 0.005 --rays 256 "
      "--formfactor-precision single -q -o ";
  std::vector<Result> results;
  ASSERT_NO_FATAL_FAILURE(solveOnEach({{1, 1}, {2, 1}, {3, 1}}, options, results));
  for (const Result& r : results) {
    EXPECT_NE(r.attributes.options.find(kPairs), std::string::npos) << r.attributes.options;
    EXPECT_EQ(testing::figure(r, "sampling_error"), 0.0);
    for (const Rgb& b : r.radiosity) ASSERT_NEAR(b[0], 1000.0, 1e-6 * 1000);
  }
  for (size_t k = 1; k < results.size(); ++k)
    for (size_t i = 0; i < results[0].radiosity.size(); ++i)
      ASSERT_NEAR(results[k].radiosity[i][0], results[0].radiosity[i][0], 1e-9 * 1000) << i;
  // --save-formfactors reads rows whole: they stay whole, and the answer is the same.
  ProgramRun whole = radiosity(2, "solve --save-formfactors" + options + path("whole.h5"));
  ASSERT_EQ(whole.exitCode, 0) << whole.output;
  const Result wholeRows = readResult(path("whole.h5"));
  EXPECT_EQ(wholeRows.attributes.options.find(kPairs), std::string::npos);
  EXPECT_TRUE(wholeRows.formFactors.has_value());
  for (const Rgb& b : wholeRows.radiosity) ASSERT_NEAR(b[0], 1000.0, 1e-6 * 1000);
}

// A box with one face lit, its reflectances given (a scene file: same geometry, other materials).
std::string litBox(const std::string& obj, double rho) {
  std::vector<Rgb> emission(6, {0, 0, 0});
  emission[0] = {1, 1, 1};
  return testing::writeBox(obj, std::vector<Rgb>(6, {rho, rho, rho}), emission);
}

const char* const kOptions =
    " --max-area 0.01 --rays 256 --refine-rounds 0 --formfactor-precision single --rtol 1e-12 -q ";

// One face lit, so that B varies: pairs once against whole rows; the walls' group factors
// (builtin:box labels them) against Howell's closed forms, exactly reciprocal.
TEST_F(EndToEnd, PairsOnceAgreeWithWholeRowsAndGiveTheWallsGroupFactors) {
  const std::string box = litBox(path("lit.obj"), 0.9);
  ASSERT_EQ(radiosity(2, "solve " + box + kOptions + "-o " + path("pairs.h5")).exitCode, 0);
  ASSERT_EQ(radiosity(2, "solve " + box + kOptions + "--save-formfactors -o " + path("whole.h5"))
                .exitCode,
            0);
  const Result pairs = readResult(path("pairs.h5")), whole = readResult(path("whole.h5"));
  ASSERT_NE(pairs.attributes.options.find(kPairs), std::string::npos);
  ASSERT_EQ(whole.attributes.options.find(kPairs), std::string::npos);
  ASSERT_EQ(pairs.radiosity.size(), whole.radiosity.size());
  double largest = 0;
  for (size_t i = 0; i < pairs.radiosity.size(); ++i)
    if (whole.radiosity[i][0] > 0)
      largest = std::max(largest, std::abs(pairs.radiosity[i][0] / whole.radiosity[i][0] - 1));
  EXPECT_GT(largest, 0);     // (not the same F: each pair's quadrature from one side)
  EXPECT_LT(largest, 1e-4);  // (what the two sides' quadratures differ by; the error is ~1e-2)
  ASSERT_EQ(
      radiosity(3, "solve builtin:box" + std::string(kOptions) + "-o " + path("walls.h5")).exitCode,
      0);
  const Result walls = readResult(path("walls.h5"));
  ASSERT_NE(walls.attributes.options.find(kPairs), std::string::npos);
  const GroupFactors& g = walls.groups;
  ASSERT_EQ(g.names.size(), 6u);
  for (size_t a = 0; a < 6; ++a)
    for (size_t b = 0; b < 6; ++b) {
      const double exact = a == b           ? 0.0
                           : a / 2 == b / 2 ? testing::parallelRectangles(1, 1, 1)
                                            : testing::perpendicularRectangles(1, 1, 1);
      EXPECT_NEAR(g.factors[a * 6 + b], exact, 1e-5) << a << " " << b;
      EXPECT_NEAR(g.factors[a * 6 + b] * g.area[a], g.factors[b * 6 + a] * g.area[b], 1e-14);
    }
}

// A checkpoint's rows stored once a pair (their rests among them) serve a restart on another
// number of ranks with other materials (F depends on the geometry only): the answer is a fresh
// run's. Whole rows asked for on the restart (--save-formfactors) are refused: the checkpoint's
// pairs cannot give them.
TEST_F(EndToEnd, PairsOnceFromACheckpointServeOtherMaterialsOnAnotherRankCount) {
  const std::string options =
      " --max-area 0.01 --rays 256 --refine-rounds 0 "
      "--formfactor-precision single --rtol 1e-12 -q ";
  const std::string first = litBox(path("first.obj"), 0.5), other = litBox(path("other.obj"), 0.8);
  ASSERT_EQ(radiosity(2, "solve " + first + options + "--checkpoint " + path("ck.h5") + " -o " +
                             path("first.h5"))
                .exitCode,
            0);
  ProgramRun restarted = radiosity(
      3, "solve " + other + options + "--restart " + path("ck.h5") + " -o " + path("restarted.h5"));
  ASSERT_EQ(restarted.exitCode, 0) << restarted.output;
  ASSERT_EQ(radiosity(1, "solve " + other + options + "-o " + path("fresh.h5")).exitCode, 0);
  const Result a = readResult(path("restarted.h5")), b = readResult(path("fresh.h5"));
  ASSERT_NE(b.attributes.options.find(kPairs), std::string::npos);
  ASSERT_EQ(a.radiosity.size(), b.radiosity.size());
  for (size_t i = 0; i < a.radiosity.size(); ++i)
    ASSERT_NEAR(a.radiosity[i][0], b.radiosity[i][0], 1e-9 * b.radiosity[i][0]) << i;
  ProgramRun whole = radiosity(2, "solve " + other + options + "--save-formfactors --restart " +
                                      path("ck.h5") + " -o " + path("whole.h5"));
  EXPECT_EQ(whole.exitCode, 3) << whole.output;
  EXPECT_NE(whole.output.find("each pair stored once there"), std::string::npos) << whole.output;
}

}  // namespace
}  // namespace radiosity
