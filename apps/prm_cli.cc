#include "apps/prm_cli.h"

#include <filesystem>
#include <sstream>
#include <vector>

namespace demfem::apps
{
  using namespace dealii;

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
    for (std::size_t i = 0; i + 1 < parts.size(); ++i)
      prm.enter_subsection(parts[i]);
    try
      {
        prm.set(parts.back(), value);
      }
    catch (...)
      {
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
          prm.leave_subsection();
        throw;
      }
    for (std::size_t i = 0; i + 1 < parts.size(); ++i)
      prm.leave_subsection();
  }

  PrmAction read_parameters(int argc, char **argv, ParameterHandler &prm,
                            const std::string &usage, std::string &file)
  {
    std::vector<std::string> overrides;
    bool                     print = false;
    for (int i = 1; i < argc; ++i)
      {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h")
          return PrmAction::help;
        else if (a == "--print-parameters")
          print = true;
        else if (a == "--set")
          {
            AssertThrow(i + 1 < argc, ExcMessage("--set needs an argument"));
            overrides.emplace_back(argv[++i]);
          }
        else if (a.rfind("--set=", 0) == 0)
          overrides.push_back(a.substr(6));
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
    if (!file.empty())
      {
        AssertThrow(std::filesystem::is_regular_file(file),
                    ExcMessage("parameter file '" + file + "' does not exist"));
        prm.parse_input(file);
      }
    else
      {
        AssertThrow(print, ExcMessage(std::string("no parameter file given\n") + usage));
      }
    for (const auto &o : overrides)
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
