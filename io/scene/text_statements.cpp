#include "io/scene/text_statements.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace radiosity::detail {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

/// Cuts a comment: '#' at the start of the text or after whitespace ("v 1 2 3 # note").
std::string_view stripComment(std::string_view s) {
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '#' && (i == 0 || isSpace(s[i - 1]))) return s.substr(0, i);
  }
  return s;
}

/// from_chars refuses a leading '+', which some OBJ writers emit. False for "", "+", "+-1".
bool stripPlus(std::string_view& text) {
  const bool plus = !text.empty() && text.front() == '+';
  if (plus) text.remove_prefix(1);
  return !text.empty() && !(plus && (text.front() == '-' || text.front() == '+'));
}

}  // namespace

bool readWholeFile(const std::string& path, std::string& content) {
  std::error_code ec;
  // Regular files only: a directory is no scene, and a device (/dev/zero) would never end.
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return false;
  content = std::move(buffer).str();
  return true;
}

StatementReader::StatementReader(std::string path, std::string content)
    : path_(std::move(path)), content_(std::move(content)) {
  if (content_.starts_with("\xEF\xBB\xBF")) pos_ = 3;  // UTF-8 byte order mark of some editors
}

std::string_view StatementReader::physicalLine() {
  // A line ends at LF, CR LF or a lone CR (the classic Mac OS files, whose text would
  // otherwise be one line and misread: "malformed number 'v'").
  size_t end = content_.find_first_of("\r\n", pos_);
  if (end == std::string::npos) end = content_.size();
  std::string_view line(content_.data() + pos_, end - pos_);
  pos_ = end + (content_.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  ++line_;
  // Control bytes never occur in OBJ/MTL text; they mean we were handed a binary file.
  for (char c : line) {
    const auto b = static_cast<unsigned char>(c);
    if ((b < 0x20 && !isSpace(c)) || b == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", b);
      throw InputError(path_, line_, std::string("not a text file (byte ") + hex + ")");
    }
  }
  return trim(line);
}

bool StatementReader::next(Statement& statement) {
  while (pos_ < content_.size()) {
    const long first = line_ + 1;
    std::string_view text = physicalLine();
    if (!text.empty() && text.back() == '\\') {  // OBJ line continuation
      joined_.assign(text.substr(0, text.size() - 1));
      while (pos_ < content_.size()) {
        std::string_view more = physicalLine();
        const bool continues = !more.empty() && more.back() == '\\';
        joined_ += ' ';
        joined_ += continues ? more.substr(0, more.size() - 1) : more;
        if (!continues) break;
      }
      text = joined_;
    }
    text = trim(stripComment(text));
    if (text.empty()) continue;
    statement.line = first;
    statement.tokens.clear();
    for (size_t i = 0; i < text.size();) {
      while (i < text.size() && isSpace(text[i])) ++i;
      size_t j = i;
      while (j < text.size() && !isSpace(text[j])) ++j;
      if (j > i) statement.tokens.push_back(text.substr(i, j - i));
      i = j;
    }
    statement.rest = trim(text.substr(statement.tokens[0].size()));
    return true;
  }
  return false;
}

NumberStatus parseNumber(std::string_view text, double& value) {
  if (!stripPlus(text)) return NumberStatus::kMalformed;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc() || end != text.data() + text.size()) return NumberStatus::kMalformed;
  return NumberStatus::kOk;
}

NumberStatus parseInteger(std::string_view text, long long& value) {
  if (!stripPlus(text)) return NumberStatus::kMalformed;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc() || end != text.data() + text.size()) return NumberStatus::kMalformed;
  return NumberStatus::kOk;
}

}  // namespace radiosity::detail
