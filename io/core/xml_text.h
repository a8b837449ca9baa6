// Text as XML character data or attribute values (the SVG plot, the XDMF sidecar): the five
// markup characters as entities, and control characters, which XML 1.0 forbids, as spaces.
#pragma once

#include <string>
#include <string_view>

namespace radiosity {

inline std::string escapeXml(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return out;
}

}  // namespace radiosity
