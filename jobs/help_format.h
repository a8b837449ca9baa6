// --help as a Unix tool prints it: wrapped to the terminal's width, 80 columns when stdout is not
// a terminal (a pipe, a file, the man page made from it), descriptions in their own column.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace radiosity::jobs {

/// The columns of the terminal on stdout; 80 when it is none (or says nothing useful).
std::size_t helpWidth();

/// `text`'s words in lines of at most `width` columns (a longer word has a line of its own),
/// joined by '\n'; the line breaks `text` has are kept.
std::string wrapped(const std::string& text, std::size_t width);

/// CLI11's help with every description wrapped to `width` columns.
class WrappedHelp : public CLI::Formatter {
 public:
  explicit WrappedHelp(std::size_t width) : width_(width) {}
  std::string make_option_desc(const CLI::Option* option) const override;
  std::string make_subcommand(const CLI::App* command) const override;
  std::string make_description(const CLI::App* app) const override;

 private:
  std::size_t width_;
  /// The width of the description column, at least 30 columns however narrow the terminal.
  std::size_t descriptionWidth() const;
};

}  // namespace radiosity::jobs
