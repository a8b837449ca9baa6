// What `radiosity solve` derives from its settings (the default output, the options line of the
// log and the result file, the form-factor options, the next round's rays) and what it records
// of its run in the result file. Plain functions, so that the pipeline (run/solve_pipeline.cpp)
// reads as its stages and these can be tested alone.
#pragma once

#include <cstdint>
#include <string>

#include "formfactor/formfactor.h"
#include "io/store/result.h"
#include "run/run_plan.h"
#include "run/solve_request.h"
#include "solve/error_calibration.h"
#include "solve/solve.h"

namespace radiosity::run {

/// The result file when -o is not given: the scene's name (builtin:NAME without its ?options,
/// or the file's stem) with .h5 (.result.h5 for a scene in HDF5), in the working directory.
std::string defaultOutput(const std::string& scene);

/// The options that shaped the run, one "name = value" line each, as the log prints them and
/// the result file keeps them (its `options` attribute).
std::string describeSettings(const SolveRequest& settings, const RunPlan& plan, double maxArea,
                             int ranks);

/// The form-factor stage's options: rays, seed, estimator (resolved, not "auto"), threads.
formfactor::Options samplingOptions(const SolveRequest& settings, const RunPlan& plan);

/// Whether F's store holds its values in single precision: --formfactor-precision single, or
/// auto where the solver does not change M's entries in place (gauss-seidel, cg) and, for
/// sampled rows, formfactor::singlePrecisionServes for the scene's largest reflectance (not in
/// a thermal run), for exact rows formfactor::singlePrecisionServesExactRows. The same on every
/// rank (every rank holds the whole scene).
bool storesSinglePrecision(const SolveRequest& settings, const RunPlan& plan, const Mesh& patches);

/// Whether exact rows are stored once a pair (SplitRows::pairsOnce), half of F: where they are
/// stored in single precision and nothing reads F's rows whole (not with --save-formfactors,
/// --reciprocity, --drop-threshold or solvers other than gmres and jacobi).
bool storesPairsOnce(const SolveRequest& settings, const RunPlan& plan, const Mesh& patches);

/// The rays per patch expected to bring the sampling error `estimated` to 80 % of `target`
/// (--target-error): at least double `rays`, at most ×16 per round and 2^24 in all.
int64_t nextRayCount(int64_t rays, double estimated, double target);

/// The solve's figures in the result's attributes: history, error estimates per channel,
/// the work done, iterations, residual, convergence and what was left out.
void recordSolve(ResultAttributes& attributes, const solve::Report& report,
                 const solve::CalibrationReport& calibration);

}  // namespace radiosity::run
