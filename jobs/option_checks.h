// The checks of option values that CLI11 lacks or gets wrong (jobs/option_checks.cpp), and the
// way --help shows a list's default; used where each command's options are declared.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity::jobs {

/// A finite number in [low, high] (`openLow`: above low); `hint` follows the refusal. CLI11's
/// own Range lets NaN through (every comparison with NaN is false) and prints its bounds in
/// full, 300 digits for DBL_MAX.
CLI::Validator finiteIn(double low, double high, bool openLow = false,
                        const std::string& hint = "");

/// A unit name for the result's labels: a short word (m, mm, ft, au), not free text.
CLI::Validator lengthUnitName();

/// A duration as batch users write it (run/duration.h).
CLI::Validator durationValue();

/// A seed: a whole number in [0, 2^64 − 1], written in decimal (no sign, no exponent), so that
/// -1 and 99999999999999999999 are refused instead of wrapping to 2^64 − 1.
CLI::Validator seedValue();

/// An option of `app` that takes one of `choices` (checked), handed to `chosen` as parsed.
CLI::Option* addChoice(CLI::App& app, const std::string& name,
                       const std::vector<std::string>& choices,
                       std::function<void(const std::string&)> chosen, const std::string& help);

/// An option of `app` that takes a number, checked by `check` (finiteIn).
CLI::Option* addNumber(CLI::App& app, const std::string& name, double& value,
                       const std::string& help, CLI::Validator check);

/// An option of `app` that takes a duration (durationValue), stored in seconds.
CLI::Option* addDuration(CLI::App& app, const std::string& name, double& seconds,
                         const std::string& help);

/// A list's default as it is typed (`16,64,256`), not as CLI11 shows it (`[16,64,256]`).
template <class T>
std::string typedList(const std::vector<T>& values) {
  std::ostringstream text;
  for (size_t i = 0; i < values.size(); ++i) text << (i ? "," : "") << values[i];
  return text.str();
}

}  // namespace radiosity::jobs
