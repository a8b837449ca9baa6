// One table per enum for its names on the command line, in the logs and in the result file: a
// constexpr array of {value, name, help} rows, read both ways by nameIn and valueNamed, and
// listed for the command line's choices by namesIn. Adding a value means adding a row; the
// command line builds its choices and help from the rows.
#pragma once

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace radiosity {

template <class Value>
struct NamedValue {
  Value value;
  const char* name;
  const char* help = "";  ///< what --help says of the choice, in parentheses after it; "": nothing
};

/// The name of `value` in `table`, or `otherwise` when no row holds it.
template <class Value, size_t N>
constexpr const char* nameIn(const NamedValue<Value> (&table)[N], Value value,
                             const char* otherwise = "unknown") {
  for (const NamedValue<Value>& row : table)
    if (row.value == value) return row.name;
  return otherwise;
}

/// The value named `name` in `table`; none for a name no row holds.
template <class Value, size_t N>
constexpr std::optional<Value> valueNamed(const NamedValue<Value> (&table)[N],
                                          std::string_view name) {
  for (const NamedValue<Value>& row : table)
    if (name == row.name) return row.value;
  return std::nullopt;
}

/// Every name of `table`, in its order (the values an option accepts).
template <class Value, size_t N>
std::vector<std::string> namesIn(const NamedValue<Value> (&table)[N]) {
  std::vector<std::string> names;
  for (const NamedValue<Value>& row : table) names.emplace_back(row.name);
  return names;
}

/// Every value of `table`, in its order (e.g. every estimator, for a sweep over all of them).
template <class Value, size_t N>
std::vector<Value> valuesIn(const NamedValue<Value> (&table)[N]) {
  std::vector<Value> values(N);
  std::ranges::transform(table, values.begin(), &NamedValue<Value>::value);
  return values;
}

/// The choices as --help lists them: each name with its help in parentheses, if it has one,
/// joined by `between`, the last by `beforeLast` ("a (help), b or c (help)").
template <class Value, size_t N>
std::string choicesDescribed(const NamedValue<Value> (&table)[N], const std::string& between = ", ",
                             const std::string& beforeLast = " or ") {
  std::string text;
  for (size_t i = 0; i < N; ++i) {
    if (i > 0) text += i + 1 == N ? beforeLast : between;
    text += table[i].name;
    if (*table[i].help) text += std::string(" (") + table[i].help + ")";
  }
  return text;
}

}  // namespace radiosity
