#include "run/duration.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>

namespace radiosity::run {

namespace {

// Above 0 and at most kLongest: a longer "limit" is a typo, and would not fit the messages' whole
// seconds.
std::optional<double> positive(double seconds) {
  constexpr double kLongest = 1e9;  // about 31 years, as --checkpoint-every's bound
  if (!std::isfinite(seconds) || seconds <= 0 || seconds > kLongest) return std::nullopt;
  return seconds;
}

// [D-]HH:MM:SS or MM:SS: whole minutes and seconds below 60, as the schedulers print them.
std::optional<double> clockTime(const std::string& text) {
  static const std::regex clock(R"(^(?:(\d+)-)?(?:(\d+):)?(\d+):(\d+)$)");
  std::smatch m;
  if (!std::regex_match(text, m, clock)) return std::nullopt;
  const auto field = [&](int k) {
    return m[k].matched ? std::strtod(m[k].str().c_str(), nullptr) : 0;
  };
  const bool hours = m[2].matched;
  if (m[1].matched && !hours) return std::nullopt;  // D-MM:SS is not a scheduler's form
  if (field(4) >= 60 || (hours && field(3) >= 60)) return std::nullopt;
  return positive(field(1) * 86400 + field(2) * 3600 + field(3) * 60 + field(4));
}

// 5400, 90m, 1.5h, 3h50m, 1h30m15s: a plain number (seconds), or numbers each followed by its
// unit, units in decreasing order and each once (1h30 is refused: 30 what?).
std::optional<double> withUnits(const std::string& text) {
  static const std::regex part(R"(^(\d+(?:\.\d*)?|\.\d+)([dhms]?))");
  const std::string units = "dhms";
  const double scale[] = {86400, 3600, 60, 1};
  double seconds = 0;
  size_t position = 0, nextUnit = 0;
  std::smatch m;
  while (position < text.size()) {
    const std::string rest = text.substr(position);
    if (!std::regex_search(rest, m, part)) return std::nullopt;
    const size_t unit = m[2].length() ? units.find(m[2].str()) : 3;
    if (unit < nextUnit) return std::nullopt;
    if (!m[2].length() && (position > 0 || static_cast<size_t>(m[0].length()) != rest.size()))
      return std::nullopt;
    seconds += std::strtod(m[1].str().c_str(), nullptr) * scale[unit];
    nextUnit = unit + 1;
    position += m[0].length();
  }
  return position == 0 ? std::nullopt : positive(seconds);
}

}  // namespace

std::optional<double> parseDuration(const std::string& text) {
  if (text.empty() || text.size() > 40) return std::nullopt;
  if (text.find(':') != std::string::npos) return clockTime(text);
  return withUnits(text);
}

std::string describeDuration(double seconds) {
  const long long whole = std::llround(seconds);
  if (whole < 60) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g s", seconds);
    return text;
  }
  std::string out;
  const long long parts[] = {whole / 86400, whole / 3600 % 24, whole / 60 % 60, whole % 60};
  const char* names[] = {"d", "h", "m", "s"};
  for (int k = 0; k < 4; ++k) {
    if (!parts[k]) continue;
    if (!out.empty()) out += ' ';
    out += std::to_string(parts[k]);
    out += names[k];
  }
  return out;
}

}  // namespace radiosity::run
