// Text from a file as it may be printed to a terminal or a message: control characters and
// bytes that are not UTF-8 as \xNN (an attribute holding ESC [ 2 J cleared the screen of
// `info`), and cut to a length (a 100 kB value used to be echoed whole).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

#include "io/core/xml_text.h"

namespace radiosity {

/// `text` escaped for a terminal and cut after `most` bytes (saying how long it was). Newlines
/// are escaped too: split the text first where lines are meant.
inline std::string shownText(std::string_view text, size_t most = 200) {
  std::string out;
  for (size_t at = 0; at < text.size() && at < most;) {
    const size_t n = utf8Length(text, at);
    const auto c = static_cast<unsigned char>(text[at]);
    if (n == 0 || c < 0x20 || c == 0x7f || c == '\\') {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, c == '\\' ? "\\\\" : "\\x%02X", c);
      out += escaped;
      ++at;
      continue;
    }
    out.append(text.substr(at, n));
    at += n;
  }
  if (text.size() > most) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace radiosity
