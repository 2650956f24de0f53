// Subsection Fit of a calibrate parameter file (docs/calibrate.md,
// "Automatic calibration"), and `demfem calibrate FILE.prm --front FIT.csv`,
// which analyses an earlier fit's log for conflicting targets ("Which
// targets conflict").
#include <deal.II/base/parameter_handler.h>

#include "apps/calibrate_fit.h"
#include "apps/cli.h"
#include "apps/output_dir.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

namespace demfem::apps
{
  using namespace dealii;

  // Subsection Fit (`--fit`): targets and searched parameters, each value
  // checked once here, naming the key (docs/calibrate.md, "Automatic
  // calibration").
  void read_fit_settings(ParameterHandler &prm, const std::string &where, FitSettings &f,
                         const std::function<void(const FitParameter &)> &check_parameter)
  {
    const auto key = [&](const std::string &k) { return where + ": Fit/" + k; };
    f.seeds        = int(parse_integer(key("seeds"), prm.get("seeds"), 1, 100));
    f.brazilian_seeds =
        int(parse_integer(key("brazilian seeds"), prm.get("brazilian seeds"), 0, 100));
    f.evaluations =
        int(parse_integer(key("evaluations"), prm.get("evaluations"), 1, 100000));
    f.algorithm = prm.get("algorithm");
    f.elastic_strain =
        parse_number(key("elastic strain"), prm.get("elastic strain"), 1e-6, 0.01);
    std::stringstream all(prm.get("parameters"));
    for (std::string item; std::getline(all, item, ';');)
      {
        std::stringstream        w(item);
        std::vector<std::string> words;
        for (std::string x; w >> x;)
          words.push_back(x);
        if (words.empty())
          continue;
        if (words.size() < 3)
          throw std::invalid_argument(key("parameters") + ": '" + item +
                                      "' is not 'name lo hi'");
        FitParameter p;
        for (std::size_t i = 0; i + 2 < words.size(); ++i)
          p.name += (i ? " " : "") + words[i];
        const std::string what = key("parameters") + " (" + p.name + ")";
        p.lo = parse_number(what + " lower bound", words[words.size() - 2], 0);
        p.hi = parse_number(what + " upper bound", words.back(), 0);
        if (!(p.hi > p.lo))
          throw std::invalid_argument(what + ": empty search space, the upper bound " +
                                      words.back() + " must exceed the lower bound " +
                                      words[words.size() - 2]);
        check_parameter(p); // a known name for this material type, sane bounds
        f.parameters.push_back(p);
      }
    prm.enter_subsection("Targets");
    for (const char *name :
         {"E", "nu", "ucs", "bts", "direct tension", "crack initiation ratio", "mi"})
      {
        const std::string text = prm.get(name);
        if (text.find_first_not_of(" \t") == std::string::npos)
          continue;
        const std::string what = key(std::string("Targets/") + name);
        const auto        v    = split_list(what, text);
        if (v.size() > 3)
          throw std::invalid_argument(what + ": 'value[, weight[, tolerance]]' expected");
        FitTarget t;
        t.name        = name;
        const bool nu = t.name == "nu", ratio = t.name == "crack initiation ratio";
        t.value = parse_number(what, v[0], nu ? 0.0 : std::nextafter(0.0, 1.0),
                               nu ? std::nextafter(0.5, 0.0)
                                  : (ratio ? 1.0 : std::numeric_limits<double>::max()));
        if (nu && !(t.value > 0))
          throw std::invalid_argument(what + ": Poisson's ratio must lie in (0, 0.5)");
        if (v.size() > 1)
          t.weight = parse_number(what + " weight", v[1], 0);
        if (v.size() > 2)
          t.tolerance = parse_number(what + " tolerance", v[2], 1e-6, 1);
        if (!(t.weight > 0))
          throw std::invalid_argument(what + " weight: must be > 0");
        f.targets.push_back(t);
      }
    prm.leave_subsection();
    auto target = [&](const std::string &n) -> const FitTarget * {
      for (const auto &t : f.targets)
        if (t.name == n)
          return &t;
      return nullptr;
    };
    if (target("direct tension") && target("ucs") &&
        target("direct tension")->value >= target("ucs")->value)
      throw std::invalid_argument(key("Targets/direct tension") +
                                  ": a direct tensile strength at or above the UCS is "
                                  "not a rock (allowed: below Fit/Targets/ucs)");
    f.resume_from = prm.get("resume from");
    if (f.resume_from.find_first_not_of(" \t") == std::string::npos)
      f.resume_from.clear();
    else if (f.enabled)
      f.replay = read_fit_log(f.resume_from, f, key("resume from"));
    if (!f.enabled)
      return;
    if (f.targets.empty())
      throw std::invalid_argument(key("Targets") + ": --fit needs at least one target");
    if (f.parameters.empty())
      throw std::invalid_argument(key("parameters") +
                                  ": --fit needs at least one parameter to search");
  }

  int run_fit_front(const ParameterHandler &prm, const std::string &where,
                    const FitSettings &fit, const std::string &out,
                    const std::string &fit_csv)
  {
    if (fit.targets.size() < 2)
      throw std::invalid_argument(where +
                                  ": Fit/Targets: --front needs at least two "
                                  "targets to compare (it gives " +
                                  std::to_string(fit.targets.size()) + ")");
    // The output directory is claimed as a run's (--overwrite deletes its
    // results): never the one holding the log being analysed.
    namespace fs = std::filesystem;
    if (fs::weakly_canonical(fs::absolute(fit_csv)).parent_path() ==
        fs::weakly_canonical(fs::absolute(out)))
      throw std::invalid_argument(where + ": Problem/output directory = " + out +
                                  " holds the log " + fit_csv +
                                  " (--front writes a run directory of its own; give "
                                  "another one)");
    const auto   evaluations = read_fit_evaluations(fit_csv, fit, "--front");
    RunDirectory run(out, prm);
    const auto   front = write_target_front(fit, evaluations, out, std::cout);
    std::cout << "demfem calibrate --front: " << evaluations.size() << " evaluations, "
              << front.pairs.size() << " target pairs -> " << out
              << "/fit_front.{csv,json,svg}, fit_levers.csv\n";
    run.finish("ok", 0);
    return 0;
  }
} // namespace demfem::apps
