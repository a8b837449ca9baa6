// Durations as batch users write them (--stop-after): plain seconds (5400), numbers with units
// (90m, 1.5h, 3h50m, 2d), or a scheduler's clock ([D-]HH:MM:SS and MM:SS, as SLURM's --time and
// PBS's walltime are written), so that a job's limit can be copied as it is.
#pragma once

#include <optional>
#include <string>

namespace radiosity::run {

/// Seconds, or nothing where `text` is not a duration, or not in (0, 10^9] seconds.
std::optional<double> parseDuration(const std::string& text);

/// "1h 30m 5s" style, for messages.
std::string describeDuration(double seconds);

}  // namespace radiosity::run
