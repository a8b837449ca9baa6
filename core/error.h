// The errors every stage throws and the exit codes they map to (the README's table).
#pragma once

#include <stdexcept>
#include <string>

namespace radiosity {

/// An error the user can act on; `exitCode` is the one the README's exit codes give it.
class Error : public std::runtime_error {
 public:
  Error(int exitCode, const std::string& message)
      : std::runtime_error(message), exitCode_(exitCode) {}
  int exitCode() const { return exitCode_; }

 private:
  int exitCode_;
};

namespace exit_code {
inline constexpr int kOk = 0;
inline constexpr int kFailure = 1;
inline constexpr int kUsage = 2;
inline constexpr int kBadInput = 3;
inline constexpr int kNumerical = 4;
inline constexpr int kStoppedBySignal = 75;
}  // namespace exit_code

/// Bad scene, material or job file. The message starts with "file:line: " where a line is known.
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(exit_code::kBadInput, message) {}
  InputError(const std::string& file, long line, const std::string& problem)
      : Error(exit_code::kBadInput, file + ":" + std::to_string(line) + ": " + problem) {}
};

}  // namespace radiosity
