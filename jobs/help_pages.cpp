// A build-time tool: the man page (radiosity.1) and the bash completion script, both made from
// the program's own command line (declareCommandLine), so that they say what it accepts.
//   help_pages man FILE          the man page: each command's --help, in roff
//   help_pages completion FILE   the bash completion: commands, options, choices, files
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "jobs/command_line.h"
#include "run/version.h"

namespace {

using radiosity::jobs::CommandLine;

std::vector<CLI::App*> commandsOf(CLI::App& app) {
  return app.get_subcommands([](CLI::App*) { return true; });
}

// Text as roff shows it verbatim: backslashes escaped, minus signs as minus (man pages keep
// option dashes apart from hyphens), a leading dot or quote neutralised.
std::string roffVerbatim(const std::string& text) {
  std::string out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && (line[0] == '.' || line[0] == '\'')) out += "\\&";
    for (char c : line) {
      if (c == '\\')
        out += "\\e";
      else if (c == '-')
        out += "\\-";
      else
        out += c;
    }
    out += '\n';
  }
  return out;
}

std::string manPage(CLI::App& app) {
  std::string version = radiosity::run::versionText();
  version = version.substr(0, version.find('\n'));
  std::ostringstream out;
  out << ".TH RADIOSITY 1 \"\" \"" << version << "\" \"User Commands\"\n"
      << ".SH NAME\nradiosity \\- diffuse global illumination and radiation exchange on MPI "
         "ranks\n"
      << ".SH SYNOPSIS\n.B mpirun \\-n\n.I N\n.B radiosity solve\n.I SCENE\n[\\fIoptions\\fR] "
         "[\\fIPETSc options\\fR]\n.br\n.B radiosity\n.I COMMAND\n[\\fIoptions\\fR]\n"
      << ".SH DESCRIPTION\n.nf\n"
      << roffVerbatim(app.help()) << ".fi\n"
      << ".SH COMMANDS\n";
  for (CLI::App* command : commandsOf(app)) {
    out << ".SS " << command->get_name() << "\n.nf\n"
        << roffVerbatim(command->help("radiosity")) << ".fi\n";
  }
  out << ".SH EXIT STATUS\n"
      << ".TP\n0\nsuccess (verify: every channel within \\-\\-tol)\n"
      << ".TP\n1\nfailure (a file that cannot be written, verify above \\-\\-tol, an MPI or "
         "HDF5 failure)\n"
      << ".TP\n2\nusage: an unknown or bad option, an output that is an input or a device\n"
      << ".TP\n3\nbad input: a scene, material, job, checkpoint or result file, named with its "
         "line\n"
      << ".TP\n4\nnumerical: the system is not solvable as given (reflectance 1 in a closed "
         "scene, the solver diverged)\n"
      << ".TP\n75\nstopped as asked (\\-\\-stop\\-after, SIGTERM, SIGUSR1): the state is in "
         "the checkpoint; run again with \\-\\-restart\n"
      << ".SH SEE ALSO\n"
      << "The documentation installed with the program (share/doc/radiosity: README.md and "
         "docs/), and\n.BR mpirun (1).\n";
  return out.str();
}

// "TEXT:{a,b,c}" → a b c; "" where the option takes no fixed choices.
std::string choicesOf(const CLI::Option* option) {
  const std::string type = option->get_type_name();
  const auto open = type.find('{'), close = type.find('}');
  if (open == std::string::npos || close == std::string::npos || close < open) return "";
  std::string words = type.substr(open + 1, close - open - 1);
  for (char& c : words)
    if (c == ',') c = ' ';
  return words;
}

std::string completion(CLI::App& app) {
  std::ostringstream out;
  std::string commands;
  for (CLI::App* command : commandsOf(app))
    commands += (commands.empty() ? "" : " ") + command->get_name();
  out << "# bash completion for radiosity, made from its command line at build time\n"
      << "_radiosity() {\n"
      << "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
      << "  local commands=\"" << commands << "\" command= word\n"
      << "  for word in \"${COMP_WORDS[@]:1:COMP_CWORD-1}\"; do\n"
      << "    case \" $commands \" in *\" $word \"*) command=$word; break ;; esac\n"
      << "  done\n"
      << "  local options=\"--help --version\"\n"
      << "  case $command in\n";
  for (CLI::App* command : commandsOf(app)) {
    std::string options = "--help", choices;
    for (const CLI::Option* option : command->get_options()) {
      if (option->get_group().empty()) continue;  // (hidden: a job file's key)
      for (const std::string& name : option->get_lnames()) {
        options += " --" + name;
        const std::string choice = choicesOf(option);
        if (!choice.empty())
          choices += "      --" + name + ") COMPREPLY=($(compgen -W \"" + choice +
                     "\" -- \"$cur\")); return ;;\n";
      }
      for (const std::string& name : option->get_snames()) options += " -" + name;
    }
    out << "    " << command->get_name() << ")\n"
        << "      options=\"" << options << "\"\n"
        << "      case $prev in\n"
        << choices << "      esac ;;\n";
  }
  out << "  esac\n"
      << "  if [[ -z $command && $cur != -* ]]; then\n"
      << "    COMPREPLY=($(compgen -W \"$commands\" -- \"$cur\")); return\n"
      << "  fi\n"
      << "  if [[ $cur == -* ]]; then\n"
      << "    COMPREPLY=($(compgen -W \"$options\" -- \"$cur\")); return\n"
      << "  fi\n"
      << "  # Scenes, results and other files; builtin: scenes are typed out.\n"
      << "  COMPREPLY=($(compgen -f -- \"$cur\"))\n"
      << "}\n"
      << "complete -o filenames -o bashdefault -F _radiosity radiosity\n";
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || (std::string(argv[1]) != "man" && std::string(argv[1]) != "completion")) {
    std::fprintf(stderr, "usage: help_pages man|completion FILE\n");
    return 2;
  }
  CLI::App app;
  CommandLine parsed;
  // (man indents the verbatim help by 7 columns: 72 keeps the page within 80)
  radiosity::jobs::declareCommandLine(app, parsed, 72);
  const std::string text = std::string(argv[1]) == "man" ? manPage(app) : completion(app);
  std::ofstream file(argv[2]);
  file << text;
  file.close();
  if (!file) {
    std::fprintf(stderr, "help_pages: cannot write %s\n", argv[2]);
    return 1;
  }
  return 0;
}
