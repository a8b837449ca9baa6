// How often a piece of text occurs in a program's output, for the tests that check each figure
// is printed once.
#pragma once

#include <string>

namespace radiosity::testing {

/// The occurrences of `what` in `text`, overlapping ones counted.
inline int occurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace radiosity::testing
