#include "jobs/help_format.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <sstream>

namespace radiosity::jobs {

std::size_t helpWidth() {
  winsize size{};
  if (isatty(STDOUT_FILENO) && ioctl(STDOUT_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 40)
    return size.ws_col;
  return 80;
}

std::string wrapped(const std::string& text, std::size_t width) {
  std::string out;
  std::istringstream paragraphs(text);
  bool firstParagraph = true;
  for (std::string paragraph; std::getline(paragraphs, paragraph);) {
    if (!firstParagraph) out += '\n';
    firstParagraph = false;
    std::istringstream words(paragraph);
    std::size_t column = 0;
    for (std::string word; words >> word;) {
      if (column > 0 && column + 1 + word.size() > width) {
        out += '\n';
        column = 0;
      } else if (column > 0) {
        out += ' ';
        ++column;
      }
      out += word;
      column += word.size();
    }
  }
  return out;
}

std::size_t WrappedHelp::descriptionWidth() const {
  return std::max<std::size_t>(30, width_ > get_column_width() ? width_ - get_column_width() : 0);
}

std::string WrappedHelp::make_option_desc(const CLI::Option* option) const {
  return wrapped(CLI::Formatter::make_option_desc(option), descriptionWidth());
}

std::string WrappedHelp::make_subcommand(const CLI::App* command) const {
  std::stringstream out;
  CLI::detail::format_help(out, command->get_display_name(true),
                           wrapped(command->get_description(), descriptionWidth()),
                           get_column_width());
  return out.str();
}

std::string WrappedHelp::make_description(const CLI::App* app) const {
  const std::string text = CLI::Formatter::make_description(app);
  // (CLI11 ends it with a line break, which wrapping would drop)
  return text.empty() ? text : wrapped(text, width_) + "\n";
}

}  // namespace radiosity::jobs
