#include "jobs/option_checks.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "run/duration.h"

namespace radiosity::jobs {

namespace {

std::string compact(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// The value as a refusal quotes it: at most 40 characters.
std::string refused(const std::string& input) {
  return "'" + (input.size() > 40 ? input.substr(0, 40) + "..." : input) + "'";
}

}  // namespace

CLI::Option* addChoice(CLI::App& app, const std::string& name,
                       const std::vector<std::string>& choices,
                       std::function<void(const std::string&)> chosen, const std::string& help) {
  return app.add_option_function<std::string>(name, std::move(chosen), help)
      ->check(CLI::IsMember(choices));
}

CLI::Option* addNumber(CLI::App& app, const std::string& name, double& value,
                       const std::string& help, CLI::Validator check) {
  return app.add_option(name, value, help)->check(std::move(check));
}

CLI::Option* addDuration(CLI::App& app, const std::string& name, double& seconds,
                         const std::string& help) {
  return app
      .add_option_function<std::string>(
          name,
          [&seconds](const std::string& text) { seconds = run::parseDuration(text).value_or(0); },
          help)
      ->check(durationValue());
}

CLI::Validator finiteIn(double low, double high, bool openLow, const std::string& hint) {
  const std::string range = (openLow ? "(" : "[") + compact(low) + ", " + compact(high) + "]";
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(input.c_str(), &end);
        if (input.empty() || end != input.c_str() + input.size() || !std::isfinite(x) || x < low ||
            x > high || (openLow && x == low))
          return refused(input) + " is not a finite number in " + range + hint;
        return std::string();
      },
      "NUMBER in " + range);
}

CLI::Validator lengthUnitName() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const bool word = !input.empty() && input.size() <= 16 &&
                          input.find_first_not_of(
                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTU"
                              "VWXYZ_") == std::string::npos;
        return word ? std::string() : "'" + input.substr(0, 40) + "' is not a unit name (letters)";
      },
      "UNIT");
}

CLI::Validator durationValue() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        if (run::parseDuration(input)) return std::string();
        return refused(input) +
               " is not a duration: above 0 and at most 1000000000 seconds, written as "
               "5400, 90m, 1.5h, 3h50m, 03:50:00 or 1-12:00:00 (no exponents)";
      },
      "DURATION");
}

CLI::Validator seedValue() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const bool digits = !input.empty() && input.size() <= 20 &&
                            input.find_first_not_of("0123456789") == std::string::npos;
        if (!digits || (input.size() == 20 && input > "18446744073709551615"))
          return refused(input) + " is not a whole number in [0, 18446744073709551615]";
        return std::string();
      },
      "UINT64");
}

}  // namespace radiosity::jobs
