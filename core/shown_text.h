// Text from a file as it may be printed to a terminal or a message: control characters and
// bytes that are not UTF-8 as \xNN (an attribute holding ESC [ 2 J cleared the screen of
// `info`), and cut to a length (a 100 kB value used to be echoed whole).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/xml_text.h"

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

/// `text` with each byte that is not part of well-formed UTF-8 written as \xNN, the rest as it
/// is: for names stored as UTF-8 (labels), which must be text whatever the file held.
inline std::string wellFormedUtf8(std::string_view text) {
  std::string out;
  for (size_t at = 0; at < text.size();) {
    const size_t n = utf8Length(text, at);
    if (n == 0) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned char>(text[at]));
      out += escaped;
      ++at;
      continue;
    }
    out.append(text.substr(at, n));
    at += n;
  }
  return out;
}

/// A message as printed (errors and warnings quote names and values from files and the command
/// line): control characters other than newline and tab, and bytes that are not UTF-8, as \xNN;
/// a run of more than 400 bytes without a space (a 100 kB value or name) cut to its first 240
/// and last 80 bytes, saying how long it was.
inline std::string shownMessage(std::string_view message) {
  constexpr size_t kLongRun = 400, kHead = 240, kTail = 80;
  std::string out;
  for (size_t at = 0; at < message.size();) {
    size_t end = at;
    while (end < message.size() && message[end] != ' ' && message[end] != '\n') ++end;
    const size_t length = end - at;
    const auto part = [&](size_t from, size_t count) {
      for (size_t k = from; k < from + count;) {
        const size_t n = utf8Length(message, k);
        const auto c = static_cast<unsigned char>(message[k]);
        if (n == 0 || k + n > from + count || (c < 0x20 && c != '\t') || c == 0x7f) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\x%02X", c);
          out += escaped;
          ++k;
          continue;
        }
        out.append(message.substr(k, n));
        k += n;
      }
    };
    if (length > kLongRun) {
      part(at, kHead);
      out += "...(" + std::to_string(length) + " bytes)...";
      part(end - kTail, kTail);
    } else {
      part(at, length);
    }
    if (end < message.size()) out += message[end];
    at = end + 1;
  }
  return out;
}

/// The last line of a run that ended with `exitCode` (not kOk), as stderr and the log file show
/// it: "radiosity: error: MESSAGE", without "error" for a stop that was asked for (exit 75).
inline std::string failureLine(int exitCode, std::string_view message) {
  return std::string("radiosity: ") + (exitCode == exit_code::kStoppedBySignal ? "" : "error: ") +
         shownMessage(message);
}

}  // namespace radiosity
