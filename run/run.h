// The run of `radiosity solve` as a library: from a request (the options, made once by the
// command line and the job file) through its stages (setup → mesh → form factors → solve →
// estimate → refine → write, run/solve_pipeline.h) to the result file. This is the folder's
// face; it knows nothing of the command line (jobs/), which fills the request.
#pragma once

#include "run/console.h"
#include "run/solve_request.h"

namespace radiosity::run {

/// Runs the solve `request` asks for; returns the exit code (every rank the same) or throws
/// radiosity::Error (run/solve_pipeline.cpp).
int runSolve(const SolveRequest& request, const Console& console);

}  // namespace radiosity::run
