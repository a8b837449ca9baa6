// Text as XML character data or attribute values (the SVG plot, the XDMF sidecar): the five
// markup characters as entities; tab, newline and carriage return as character references (an
// attribute value would turn them into spaces); what XML 1.0 cannot hold at all as something it
// can (other control characters as spaces, bytes that are not UTF-8 as U+FFFD), so that the
// document stays well-formed.
#pragma once

#include <string>
#include <string_view>

namespace radiosity {

/// The length of the well-formed UTF-8 sequence at text[at] (1 to 4), 0 if there is none.
inline size_t utf8Length(std::string_view text, size_t at) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[at + k]); };
  const unsigned char b = byte(0);
  if (b < 0x80) return 1;
  const size_t n = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC2 ? 2 : 0;
  if (n == 0 || b > 0xF4 || at + n > text.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((byte(k) & 0xC0) != 0x80) return 0;
  // No overlong forms, surrogates or code points past U+10FFFF.
  if ((b == 0xE0 && byte(1) < 0xA0) || (b == 0xED && byte(1) >= 0xA0) ||
      (b == 0xF0 && byte(1) < 0x90) || (b == 0xF4 && byte(1) >= 0x90))
    return 0;
  return n;
}

/// Whether XML 1.0 holds `text` as it is: well-formed UTF-8 without control characters other
/// than tab, newline and carriage return. (A file name that is not must not be written into a
/// sidecar: a replaced character would name another file.)
inline bool xmlHolds(std::string_view text) {
  for (size_t at = 0; at < text.size();) {
    const size_t n = utf8Length(text, at);
    const auto c = static_cast<unsigned char>(text[at]);
    if (n == 0 || (c < 0x20 && c != '\t' && c != '\n' && c != '\r')) return false;
    at += n;
  }
  return true;
}

inline std::string escapeXml(std::string_view text) {
  std::string out;
  for (size_t at = 0; at < text.size();) {
    const size_t n = utf8Length(text, at);
    const char c = text[at];
    if (n == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD for a byte that is not UTF-8
      ++at;
      continue;
    }
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      case '\t':
        out += "&#9;";
        break;
      case '\n':
        out += "&#10;";
        break;
      case '\r':
        out += "&#13;";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += ' ';
        else
          out.append(text.substr(at, n));
    }
    at += n;
  }
  return out;
}

}  // namespace radiosity
