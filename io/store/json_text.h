// What the --json summaries share (`info`'s in io/store/result_info_json.cpp, `solve`'s and
// `verify`'s in jobs/json_summaries.cpp): documents whose keys stay in the order written (schema
// first), per-channel figures keyed by channel name, and the text of a document.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <string>

#include "core/channels.h"

namespace radiosity {

using JsonDocument = nlohmann::ordered_json;

/// {"red": x, "green": y, "blue": z}, or {"grey": x} for a one-channel (thermal) result.
inline JsonDocument perChannelJson(int channels, const std::array<double, 3>& value) {
  JsonDocument out = JsonDocument::object();
  for (int c = 0; c < (channels == 1 ? 1 : 3); ++c) out[channelName(c, channels)] = value[c];
  return out;
}

/// The document as text, indented. Text from users (paths, messages) may hold bytes that are
/// not UTF-8: they become U+FFFD rather than a failure.
inline std::string jsonText(const JsonDocument& document) {
  return document.dump(2, ' ', false, JsonDocument::error_handler_t::replace);
}

}  // namespace radiosity
