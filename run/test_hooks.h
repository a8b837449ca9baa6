// Hooks that let the tests hit a moment of a run that is otherwise too short to aim a signal at.
// Inert unless their environment variable is set.
#pragma once

namespace radiosity::run {

/// RADIOSITY_TEST_STAGE_STALL="STAGE SECONDS" (e.g. "load 3"): sleeps SECONDS at the end of
/// stage STAGE ("load", "mesh", "refine": each refinement round), signals notwithstanding.
/// Nothing otherwise.
void stallForTests(const char* stage);

}  // namespace radiosity::run
