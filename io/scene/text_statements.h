// Private to io/: line-oriented text input shared by the OBJ and MTL readers.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace radiosity::detail {

/// Reads a whole file into `content`. Returns false if it cannot be opened or read.
bool readWholeFile(const std::string& path, std::string& content);

/// One statement: a non-blank line with comments, line end and '\' continuations removed.
struct Statement {
  long line = 0;                         ///< 1-based line the statement starts on
  std::vector<std::string_view> tokens;  ///< whitespace-separated; tokens[0] is the keyword
  std::string_view rest;                 ///< text after the keyword, trimmed (names with spaces)
};

/// Hands out the statements of a text file in order; lines end at LF, CR LF or a lone CR.
/// Refuses binary content (control bytes) with an InputError naming the file and line. Bytes
/// that are not UTF-8 are kept (a name in Latin-1: validateScene stores it as \xNN, warning).
/// The views in a Statement stay valid until the next call to next().
class StatementReader {
 public:
  StatementReader(std::string path, std::string content);
  bool next(Statement& statement);
  const std::string& path() const { return path_; }

 private:
  std::string_view physicalLine();

  std::string path_;
  std::string content_;
  std::string joined_;  ///< backing store of a statement continued over several lines
  size_t pos_ = 0;
  long line_ = 0;
};

enum class NumberStatus { kOk, kMalformed, kOutOfRange };

/// Parses the whole of `text` as a decimal number ("+1.5", "-2e3", "nan" and "inf" included;
/// the caller decides about non-finite values). Locale independent.
NumberStatus parseNumber(std::string_view text, double& value);

/// Parses the whole of `text` as a decimal integer with optional sign.
NumberStatus parseInteger(std::string_view text, long long& value);

}  // namespace radiosity::detail
