// What `radiosity solve` derives from its settings and records of its run (solve_settings.h).
#include "run/derived_settings.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/channels.h"
#include "io/scene/scene.h"
#include "run/request_options.h"

namespace radiosity::run {

std::string defaultOutput(const std::string& scene) {
  std::string stem =
      scene.rfind("builtin:", 0) == 0
          ? scene.substr(
                8, scene.find('?') == std::string::npos ? std::string::npos : scene.find('?') - 8)
          : std::filesystem::path(scene).stem().string();
  // A scene in HDF5 would otherwise be its own result's name.
  return stem + (isHdf5Scene(scene) ? ".result.h5" : ".h5");
}

std::string describeSettings(const SolveRequest& s, const RunPlan& plan, double maxArea,
                             int ranks) {
  const RunShown shown{s, plan, maxArea};
  std::ostringstream text;
  for (const RequestOption& option : requestOptions()) {
    const std::string value = option.echo ? option.echo(shown) : std::string();
    if (!value.empty()) text << option.key() << " = " << value << "\n";
  }
  text << "ranks = " << ranks << "\n";
  if (plan.exactRows)  // chosen for the scene (formfactor::chooseRows)
    text << (plan.pairsOnce ? "rows = exact, each pair stored once\n" : "rows = exact\n");
  if (plan.singlePrecision) text << "values = single\n";  // chosen (storesSinglePrecision)
  return text.str();
}

formfactor::Options samplingOptions(const SolveRequest& s, const RunPlan& plan) {
  formfactor::Options options;
  options.raysPerPatch = plan.rays;
  options.seed = s.seed;
  options.estimator = plan.estimator.value_or(formfactor::Estimator::kHemisphere);
  options.threads = s.threads;
  options.exactRows = plan.exactRows;
  options.singlePrecision = plan.singlePrecision;
  options.pairsOnce = plan.pairsOnce;
  return options;
}

bool storesSinglePrecision(const SolveRequest& s, const RunPlan& plan, const Mesh& patches) {
  const int64_t samples = plan.rays;
  if (s.valuePrecision == ValuePrecision::kDouble) return false;
  if (s.valuePrecision == ValuePrecision::kSingle) return samples < formfactor::kExactSumSamples;
  if (s.solver == solve::Solver::kGaussSeidel || s.solver == solve::Solver::kCg) return false;
  // (exact rows keep their sums on floats, and thermal runs balance no exact column)
  if (plan.exactRows)
    return formfactor::singlePrecisionServesExactRows(patches.triangleCount(), samples);
  if (!s.thermal.empty()) return false;  // the heat rates' balance wants doubles (balanceColumns)
  double largest = 0;
  for (const Rgb& rho : patches.reflectance) largest = std::max({largest, rho[0], rho[1], rho[2]});
  return formfactor::singlePrecisionServes(samples, largest);
}

bool storesPairsOnce(const SolveRequest& s, const RunPlan& plan, const Mesh& patches) {
  if (!plan.exactRows || !storesSinglePrecision(s, plan, patches)) return false;
  if (s.saveFormFactors || plan.reciprocity || s.dropThreshold > 0) return false;
  return !s.solver || *s.solver == solve::Solver::kGmres || *s.solver == solve::Solver::kJacobi;
}

// The sampling error falls like N^-2/3 with the scrambled Sobol' points (docs/accuracy.md), so N
// grows by the error's ratio to the power 3/2.
int64_t nextRayCount(int64_t rays, double estimated, double target) {
  const double factor = std::clamp(std::pow(estimated / (0.8 * target), 1.5), 2.0, 16.0);
  return std::min<int64_t>(int64_t{1} << 24, static_cast<int64_t>(std::ceil(rays * factor)));
}

void recordSolve(ResultAttributes& attributes, const solve::Report& report,
                 const solve::CalibrationReport& calibration) {
  attributes.history = report.history;
  attributes.solveFigures = {{"error_bound", report.errorBound},
                             {"error_estimate", report.relativeStderr},
                             {"sampling_error", report.samplingShare},
                             {"discretisation_error", report.discretisationShare},
                             {"error_calibration_rays", static_cast<double>(calibration.rays)},
                             {"contraction", report.contraction},
                             {"condition_estimate", report.conditionEstimate},
                             {"unknowns", static_cast<double>(report.unknowns)},
                             {"matrix_products", static_cast<double>(report.matrixProducts)},
                             {"nonzero_products", static_cast<double>(report.nonzeroProducts)},
                             {"channels_solved", static_cast<double>(report.channelsSolved)}};
  for (int c = 0; c < 3; ++c) {
    const std::string channel = kChannelNames[c];
    attributes.solveFigures["sampling_error_B_" + channel] = report.samplingErrorB[c];
    attributes.solveFigures["sampling_error_H_" + channel] = report.samplingErrorH[c];
    attributes.solveFigures["discretisation_error_B_" + channel] = report.discretisationErrorB[c];
    attributes.solveFigures["error_estimate_B_" + channel] = report.errorB[c];
    attributes.solveFigures["error_estimate_H_" + channel] = report.errorH[c];
    attributes.solveFigures["error_scale_indirect_" + channel] = report.calibration.indirect[c];
    attributes.solveFigures["error_scale_direct_" + channel] = report.calibration.direct[c];
    attributes.solveFigures["solver_error_" + channel] = report.solverError[c];
  }
  attributes.iterations = report.iterations;
  attributes.residual = report.residual;
  attributes.converged = report.converged;
  attributes.leftOut = report.leftOut;
}

}  // namespace radiosity::run
