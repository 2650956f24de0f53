#include "apps/prm_cli.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace demfem::apps
{
  using namespace dealii;

  const char *common_options_help =
      "  --set \"Section/key=value\"  override a key (repeatable; after the file)\n"
      "  --defaults          allow a parameter file that sets no key (or none at all):\n"
      "                      every key at its default; without it such a file is an\n"
      "                      error, since it is usually a mistake\n"
      "  --overwrite         the output directory holds an earlier run: delete its\n"
      "                      results (frames, checkpoint, history, summary) and run;\n"
      "                      without it such a directory is refused\n"
      "  --print-parameters  print every key with its default and doc, then exit\n"
      "  --help              print this text\n";

  namespace
  {
    CommandLine the_command_line;

    /// Whether a parameter file sets at least one key. A .prm file without
    /// any `set` line (empty, or comments only) is almost always a wrong
    /// file, and would run every default silently.
    bool sets_a_key(const std::string &file)
    {
      std::ifstream in(file);
      const auto    ext = std::filesystem::path(file).extension().string();
      if (ext == ".json" || ext == ".xml")
        {
          std::stringstream s;
          s << in.rdbuf();
          return s.str().find(ext == ".json" ? "\"value\"" : "<value>") !=
                 std::string::npos;
        }
      for (std::string line; std::getline(in, line);)
        {
          line = line.substr(0, line.find('#'));
          std::istringstream words(line);
          std::string        first;
          if (words >> first && first == "set")
            return true;
        }
      return false;
    }
  } // namespace

  std::string exception_text(const std::exception &e)
  {
    if (const auto *d = dynamic_cast<const ExceptionBase *>(&e))
      {
        std::ostringstream s;
        d->print_info(s);
        const std::string t = s.str();
        const auto        b = t.find_first_not_of(" \n\t");
        const auto        l = t.find_last_not_of(" \n\t");
        return b == std::string::npos ? d->get_exc_name() : t.substr(b, l - b + 1);
      }
    return e.what();
  }

  const CommandLine &command_line() { return the_command_line; }

  std::string key_name(const std::string &key_path)
  {
    for (auto o = the_command_line.overrides.rbegin();
         o != the_command_line.overrides.rend(); ++o)
      if (o->compare(0, key_path.size() + 1, key_path + "=") == 0)
        return key_path + " (--set)";
    if (the_command_line.file.empty())
      return key_path + " (default)";
    return key_path + " (parameter file '" + the_command_line.file + "')";
  }

  std::string resolve_input_file(const std::string &path)
  {
    namespace fs = std::filesystem;
    if (path.empty() || fs::path(path).is_absolute() || fs::exists(path) ||
        command_line().file.empty())
      return path;
    const fs::path beside = fs::path(command_line().file).parent_path() / path;
    return fs::exists(beside) ? beside.string() : path;
  }

  std::string shell_quoted(const std::vector<std::string> &arguments)
  {
    std::string r;
    for (const auto &a : arguments)
      {
        if (!r.empty())
          r += ' ';
        const bool plain =
            !a.empty() &&
            a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQ"
                                "RSTUVWXYZ0123456789_./=:,+-@%") == std::string::npos;
        if (plain)
          r += a;
        else
          {
            r += '\'';
            for (char c : a)
              r += c == '\'' ? std::string("'\\''") : std::string(1, c);
            r += '\'';
          }
      }
    return r;
  }

  void apply_override(ParameterHandler &prm, const std::string &arg)
  {
    const auto eq = arg.find('=');
    AssertThrow(eq != std::string::npos && eq > 0,
                ExcMessage("--set expects \"Section/key=value\", got \"" + arg + "\""));
    const std::string        path = arg.substr(0, eq), value = arg.substr(eq + 1);
    std::vector<std::string> parts;
    std::stringstream        ss(path);
    for (std::string p; std::getline(ss, p, '/');)
      parts.push_back(p);
    AssertThrow(parts.size() >= 2, ExcMessage("--set \"" + arg +
                                              "\": the key needs its section, "
                                              "e.g. \"Tunnel/radius=1.5\""));
    // ParameterHandler::enter_subsection creates a section it does not know,
    // so a misspelled one would surface as an unknown key: name it here.
    const std::vector<std::string> sections(parts.begin(), parts.end() - 1);
    for (std::size_t i = 1; i <= sections.size(); ++i)
      AssertThrow(prm.subsection_path_exists({sections.begin(), sections.begin() + i}),
                  ExcMessage("unknown section '" + sections[i - 1] +
                             "' (--print-parameters lists the sections and keys)"));
    for (const auto &s : sections)
      prm.enter_subsection(s);
    try
      {
        prm.set(parts.back(), value);
      }
    catch (...)
      {
        for (std::size_t i = 0; i < sections.size(); ++i)
          prm.leave_subsection();
        throw;
      }
    for (std::size_t i = 0; i < sections.size(); ++i)
      prm.leave_subsection();
  }

  bool answered(const PrmAction action, const ParameterHandler &prm,
                const std::string &usage, std::ostream *out)
  {
    if (action == PrmAction::help && out)
      *out << usage << common_options_help;
    if (action == PrmAction::print && out)
      prm.print_parameters(*out, ParameterHandler::Text);
    return action != PrmAction::run;
  }

  PrmAction read_parameters(int argc, char **argv, ParameterHandler &prm,
                            const std::string &usage, std::string &file)
  {
    CommandLine &cl = the_command_line;
    cl              = CommandLine();
    cl.command      = argc > 0 ? argv[0] : "";
    bool print      = false;
    for (int i = 1; i < argc; ++i)
      {
        const std::string a = argv[i];
        cl.arguments.push_back(a);
        if (a == "--help" || a == "-h")
          return PrmAction::help;
        else if (a == "--print-parameters")
          print = true;
        else if (a == "--defaults")
          cl.defaults = true;
        else if (a == "--overwrite")
          cl.overwrite = true;
        else if (a == "--set")
          {
            AssertThrow(i + 1 < argc, ExcMessage("--set needs an argument"));
            cl.overrides.emplace_back(argv[++i]);
            cl.arguments.push_back(argv[i]);
          }
        else if (a.rfind("--set=", 0) == 0)
          cl.overrides.push_back(a.substr(6));
        else if (a.rfind("-", 0) == 0)
          {
            AssertThrow(false, ExcMessage("unknown option '" + a + "' (see --help)"));
          }
        else
          {
            AssertThrow(file.empty(), ExcMessage("more than one parameter file given"));
            file = a;
          }
      }
    cl.file = file;
    if (!file.empty())
      {
        AssertThrow(
            !std::filesystem::is_directory(file),
            ExcMessage("parameter file '" + file + "' is a directory, not a .prm file"));
        AssertThrow(std::filesystem::is_regular_file(file),
                    ExcMessage("parameter file '" + file + "' does not exist"));
        AssertThrow(print || cl.defaults || sets_a_key(file),
                    ExcMessage("parameter file '" + file +
                               "' sets no key (empty, or comments only); pass "
                               "--defaults to run with every key at its default"));
        prm.parse_input(file);
      }
    else
      {
        AssertThrow(print || cl.defaults,
                    ExcMessage(std::string("no parameter file given (--defaults runs "
                                           "with every key at its default)\n") +
                               usage));
      }
    for (const auto &o : cl.overrides)
      try
        {
          apply_override(prm, o);
        }
      catch (const std::exception &e)
        {
          AssertThrow(false, ExcMessage("--set \"" + o + "\": " + exception_text(e)));
        }
    return print ? PrmAction::print : PrmAction::run;
  }

  void declare_in_situ_stress(dealii::ParameterHandler &prm)
  {
    for (const std::string c : {"xx", "yy", "zz", "xy", "xz", "yz"})
      prm.declare_entry("in situ stress " + c,
                        c == "xx"   ? "-30e6"
                        : c == "yy" ? "-60e6"
                        : c == "zz" ? "-45e6"
                                    : "0",
                        dealii::Patterns::Double(),
                        "In-situ stress component " + c +
                            " [Pa], tension positive; z is the tunnel axis (2D uses "
                            "xx, yy, xy)");
  }
} // namespace demfem::apps
