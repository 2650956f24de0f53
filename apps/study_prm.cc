// Parameters of `demfem study`: the `Study` subsection (the values to sweep,
// right-sizing); the tunnel keys are apps/tunnel_prm.h, declared by both
// commands so that a tunnel file can be swept as it is.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include "apps/cli.h"
#include "apps/prm_cli.h"
#include "apps/study.h"
#include "dem/specimen/material_file.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace demfem::apps::study
{
  using namespace dealii;

  void declare_study_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Study");
    prm.declare_entry("region radius factors", "", Patterns::Anything(),
                      "Comma-separated DEM-region radii / tunnel radius to sweep; "
                      "'auto' is the right-sized radius. Empty: DEM region/radius");
    prm.declare_entry("grain resolutions", "", Patterns::Anything(),
                      "Comma-separated a/d (tunnel radius / mean grain diameter) to "
                      "sweep; the size ratio d_max/d_min is kept. Empty: as given");
    prm.declare_entry("subcycles", "", Patterns::Anything(),
                      "Comma-separated DEM steps per continuum step. Empty: "
                      "Coupling/subcycles");
    prm.declare_entry("timestep safety factors", "", Patterns::Anything(),
                      "Comma-separated time-step safety factors. Empty: "
                      "Coupling/timestep safety");
    prm.declare_entry("seeds", "", Patterns::Anything(),
                      "Comma-separated packing seeds: repeats each setting on other "
                      "packings (the error of a coarse region depends on its packing). "
                      "Empty: DEM region/seed");
    prm.declare_entry("damage threshold", "0.4", Patterns::Double(0),
                      "Right-sizing: damage initiates where sigma1 - sigma3 >= this x "
                      "UCS (Martin et al. 1999)");
    prm.declare_entry("ucs", "0", Patterns::Double(0),
                      "UCS [Pa] for the right-sizing; 0: \"ucs\" of DEM "
                      "region/material file");
    prm.declare_entry("margin grains", "3", Patterns::Double(0),
                      "Right-sizing margin in mean grain diameters");
    prm.declare_entry("coupling variants", "", Patterns::Anything(),
                      "Comma-separated Coupling/variant values (wall-facets, "
                      "slaved-layer). Empty: Coupling/variant");
    prm.declare_entry("schemes", "", Patterns::Anything(),
                      "Comma-separated Coupling/scheme values (explicit, "
                      "quasi-static, condensed). Empty: Coupling/scheme");
    prm.declare_entry("relaxation factors", "", Patterns::Anything(),
                      "Comma-separated Coupling/relaxation values in (0, 2). Empty: "
                      "Coupling/relaxation");
    prm.declare_entry("stiffness contrasts", "", Patterns::Anything(),
                      "Comma-separated DEM/continuum stiffness contrasts: "
                      "Continuum/young modulus = this x the material's E (1: matched). "
                      "Empty: 1");
    prm.declare_entry("breakable", "false", Patterns::Bool(),
                      "true: breakable bonds, each run compared with a full-DEM "
                      "reference (damage-zone depth, crack counts) instead of Kirsch; "
                      "writes study_speedup.csv and study.md");
    prm.declare_entry("reference radius factor", "8", Patterns::Double(),
                      "Breakable mode: radius of the full-DEM reference domain / "
                      "tunnel radius, in [8, 100]");
    prm.declare_entry("servo tolerance", "0.02", Patterns::Double(),
                      "Breakable mode: the reference's membrane holds the in-situ "
                      "stress within this relative error, in (0, 0.5]");
    prm.declare_entry("agreement tolerance", "0.1", Patterns::Double(),
                      "Breakable mode: equal damage-zone depth and damaged area, "
                      "each within +- this fraction of the reference's, in (0, 1]");
    prm.leave_subsection();
  }

  namespace
  {
    std::vector<std::string> split(ParameterHandler &prm, const std::string &key)
    {
      return split_list(key_name("Study/" + key), prm.get(key));
    }

    double number(const std::string &key, const std::string &t, double lo, double hi)
    {
      return parse_number(key_name("Study/" + key), t, lo, hi);
    }
  } // namespace

  Settings read_study_settings(ParameterHandler &prm, const std::string &material_file)
  {
    Settings s;
    prm.enter_subsection("Study");
    for (const auto &t : split(prm, "region radius factors"))
      s.radius_factors.push_back(t == "auto" ? std::optional<double>()
                                             : std::optional<double>(number(
                                                   "region radius factors", t, 1, 1e3)));
    for (const auto &t : split(prm, "grain resolutions"))
      s.resolutions.push_back(number("grain resolutions", t, 1, 1e3));
    for (const auto &t : split(prm, "subcycles"))
      s.subcycles.push_back(static_cast<unsigned int>(
          parse_integer(key_name("Study/subcycles"), t, 1, 1000)));
    for (const auto &t : split(prm, "timestep safety factors"))
      s.safeties.push_back(number("timestep safety factors", t, 1e-3, 100));
    for (const auto &t : split(prm, "seeds"))
      s.seeds.push_back(static_cast<std::uint64_t>(
          parse_integer(key_name("Study/seeds"), t, 0, 1000000000000000LL)));
    s.damage_fraction = prm.get_double("damage threshold");
    s.ucs             = prm.get_double("ucs");
    s.margin_grains   = prm.get_double("margin grains");
    for (const auto &t : split(prm, "coupling variants"))
      {
        AssertThrow(
            t == "wall-facets" || t == "slaved-layer",
            ExcMessage("Study/coupling variants: '" + t +
                       "' is not a variant (allowed: wall-facets, slaved-layer)"));
        s.variants.push_back(t);
      }
    for (const auto &t : split(prm, "schemes"))
      {
        AssertThrow(t == "explicit" || t == "quasi-static" || t == "condensed",
                    ExcMessage("Study/schemes: '" + t +
                               "' is not a scheme (allowed: explicit, quasi-static, "
                               "condensed)"));
        s.schemes.push_back(t);
      }
    for (const auto &t : split(prm, "relaxation factors"))
      {
        s.relaxations.push_back(number("relaxation factors", t, 0, 2));
        AssertThrow(s.relaxations.back() > 0 && s.relaxations.back() < 2,
                    ExcMessage("Study/relaxation factors: '" + t +
                               "' is not in the open interval (0, 2)"));
      }
    for (const auto &t : split(prm, "stiffness contrasts"))
      {
        s.stiffness_contrasts.push_back(number("stiffness contrasts", t, 0, 1e3));
        AssertThrow(s.stiffness_contrasts.back() > 0,
                    ExcMessage("Study/stiffness contrasts: '" + t + "' must be > 0"));
      }
    s.breakable = prm.get_bool("breakable");
    s.reference_radius_factor =
        number("reference radius factor", prm.get("reference radius factor"), 8, 100);
    s.servo_tolerance = number("servo tolerance", prm.get("servo tolerance"), 1e-6, 0.5);
    s.agreement_tolerance =
        number("agreement tolerance", prm.get("agreement tolerance"), 1e-6, 1);
    prm.leave_subsection();
    if (s.ucs == 0 && !material_file.empty())
      {
        check_material_file("DEM region/material file", material_file);
        const double ucs = dem::read_material_number(material_file, "ucs", false);
        s.ucs            = std::isfinite(ucs) ? ucs : 0.0; // null: not measured
      }
    return s;
  }
} // namespace demfem::apps::study
