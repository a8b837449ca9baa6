// Two spellings of one name: "Küche" typed as K, ü, c, h, e (composed, NFC, as most editors
// write it) and as K, u, U+0308, c, h, e (decomposed, NFD, as macOS file names and some
// exporters write it) look alike but are other bytes, so they do not match. No normaliser here
// (no ICU in the stack): names compare as bytes, and where a name matches none, the one that
// differs only by combining marks (U+0300 to U+036F) on Latin letters is named with its code
// points, so the refusal says why identical-looking names differ.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "core/xml_text.h"

namespace radiosity {

namespace unicode_spelling_detail {

// The code point of the UTF-8 sequence of `n` bytes at `at` (n from utf8Length, 1 to 4).
inline uint32_t codePointAt(std::string_view text, size_t at, size_t n) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[at + k]); };
  if (n == 1) return byte(0);
  uint32_t c = byte(0) & (0x7f >> n);
  for (size_t k = 1; k < n; ++k) c = c << 6 | (byte(k) & 0x3f);
  return c;
}

// The base letter of a precomposed Latin letter (U+00C0 to U+017F) that decomposes to a letter
// and combining marks; 0 where it does not (Æ, Ø, ß, Ł, ...) or is no letter.
inline char baseLetter(uint32_t c) {
  static constexpr const char* kLatin1 =  // U+00C0 to U+00FF
      "AAAAAA?CEEEEIIII?NOOOOO??UUUUY??aaaaaa?ceeeeiiii?nooooo??uuuuy?y";
  static constexpr const char* kExtendedA =  // U+0100 to U+017F
      "AaAaAaCcCcCcCcDd??EeEeEeEeEeGgGgGgGgHh??IiIiIiIiI???JjKk?LlLlLl?"
      "???NnNnNn???OoOoOo??RrRrRrSsSsSsSsTtTt??UuUuUuUuUuUuWwYyYZzZzZz?";
  const char base = c >= 0xc0 && c < 0x100    ? kLatin1[c - 0xc0]
                    : c >= 0x100 && c < 0x180 ? kExtendedA[c - 0x100]
                                              : '?';
  return base == '?' ? 0 : base;
}

}  // namespace unicode_spelling_detail

/// A combining diacritical mark (U+0300 to U+036F): what NFD writes after a letter.
inline bool isCombiningMark(uint32_t c) { return c >= 0x300 && c <= 0x36f; }

/// `name` without its accents: combining marks dropped and precomposed Latin letters written
/// as their base letter, so that the NFC and NFD spellings of a name give the same key.
inline std::string spellingKey(std::string_view name) {
  using namespace unicode_spelling_detail;
  std::string key;
  for (size_t at = 0; at < name.size();) {
    const size_t n = utf8Length(name, at);
    if (n == 0) {  // (not UTF-8: kept as it is)
      key += name[at++];
      continue;
    }
    const uint32_t c = codePointAt(name, at, n);
    if (const char base = baseLetter(c))
      key += base;
    else if (!isCombiningMark(c))
      key.append(name.substr(at, n));
    at += n;
  }
  return key;
}

/// `name` with every character outside printable ASCII as \uXXXX (bytes that are not UTF-8 as
/// \xNN): two spellings side by side show where they differ.
inline std::string codePointsShown(std::string_view name, size_t most = 80) {
  using namespace unicode_spelling_detail;
  std::string out;
  for (size_t at = 0; at < name.size() && at < most;) {
    const size_t n = utf8Length(name, at);
    const auto byte = static_cast<unsigned char>(name[at]);
    char escaped[16];
    if (n == 0) {
      std::snprintf(escaped, sizeof escaped, "\\x%02X", byte);
      out += escaped;
      ++at;
      continue;
    }
    const uint32_t c = codePointAt(name, at, n);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out += static_cast<char>(c);
    } else {
      std::snprintf(escaped, sizeof escaped, c > 0xffff ? "\\U%08X" : "\\u%04X", c);
      out += escaped;
    }
    at += n;
  }
  if (name.size() > most) out += "...";
  return out;
}

/// The accents `name` carries: its combining marks (NFD) and its precomposed letters (NFC).
/// Whether it has any combining mark in `decomposed`.
inline int accentCount(std::string_view name, bool* decomposed = nullptr) {
  using namespace unicode_spelling_detail;
  int count = 0;
  for (size_t at = 0; at < name.size();) {
    const size_t n = utf8Length(name, at);
    if (n > 1) {
      const uint32_t c = codePointAt(name, at, n);
      const bool mark = isCombiningMark(c);
      if (mark && decomposed) *decomposed = true;
      count += mark || baseLetter(c) != 0;
    }
    at += n == 0 ? 1 : n;
  }
  return count;
}

/// Where `given` matches none of `names` but one of them has the same letters and as many
/// accents spelt otherwise (one of the two with combining marks, NFD): a clause naming both
/// with their code points; empty otherwise. For a refusal that lists the names, which would
/// look identical to the one given.
inline std::string spellingDifference(std::string_view given,
                                      const std::vector<std::string>& names) {
  const std::string key = spellingKey(given);
  bool givenDecomposed = false;
  const int accents = accentCount(given, &givenDecomposed);
  const auto form = [](bool decomposed) {
    return decomposed ? "decomposed accents, NFD" : "composed accents, NFC";
  };
  for (const std::string& name : names) {
    bool nameDecomposed = false;
    if (name == given || spellingKey(name) != key ||
        accentCount(name, &nameDecomposed) != accents || !(givenDecomposed || nameDecomposed))
      continue;
    std::string text(1, '\'');  // (appended: GCC 12 warns of "'" + a string, -Wrestrict)
    text.append(codePointsShown(given)).append("' (").append(form(givenDecomposed));
    text.append(") is spelt in other Unicode code points than the scene's '");
    text.append(codePointsShown(name)).append("' (").append(form(nameDecomposed));
    return text.append("), though they look alike: write it as the scene does");
  }
  return "";
}

}  // namespace radiosity
