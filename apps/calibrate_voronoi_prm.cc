// Parameters of `demfem calibrate` for Voronoi grains (calibrate_voronoi.h):
// subsection Material/Voronoi, and the keys of the other subsections that
// mean the same for Voronoi grains as for the bonded-particle materials.
// Every value is checked once, here, naming the key, the file and the
// allowed range (docs/architecture.md, "Input validation").
#include <deal.II/base/utilities.h>

#include "apps/calibrate_voronoi.h"
#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace demfem::apps
{
  namespace
  {
    using namespace dealii;
    namespace vor = dem::voronoi;

    void check(const std::string &where, const std::string &key, double v, double lo,
               double hi, bool lo_open = false, bool hi_open = false)
    {
      dem::check_range(where, key, v, lo, hi, lo_open, hi_open);
    }

    [[noreturn]] void refuse(const std::string &where, const std::string &what)
    {
      throw dem::InputError(where + ": " + what);
    }

    // Material/size distribution as the [d_min, d_max] of the Voronoi
    // specimen: its packing draws diameters uniformly (voronoi_lab_test.h).
    void read_sizes(const std::string &text, const std::string &where,
                    vor::VoronoiSpecimenParams &p)
    {
      const std::string key = "Material/size distribution";
      std::stringstream in(text);
      std::string       kind, tail;
      double            lo = 0, hi = 0, fraction = 0;
      if (!(in >> kind >> lo >> hi >> fraction) || kind != "uniform" || (in >> tail) ||
          text.find(';') != std::string::npos)
        refuse(where, key + ": '" + text +
                          "' (allowed for Voronoi grains: one piece 'uniform D_lo D_hi "
                          "1', the packing's diameters are uniform)");
      check(where, key + " (D_lo)", lo, 0, HUGE_VAL, true);
      check(where, key + " (D_hi)", hi, lo, HUGE_VAL);
      check(where, key + " (volume fraction)", fraction, 1, 1);
      p.d_min = lo, p.d_max = hi;
    }
  } // namespace

  bool is_voronoi_type(const std::string &type)
  {
    return type == "rigid-voronoi" || type == "flexible-voronoi";
  }

  const char *voronoi_type_names() { return "rigid-voronoi|flexible-voronoi"; }

  void declare_voronoi_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Voronoi");
    prm.declare_entry(
        "contact modulus", "50e9", Patterns::Double(),
        "E_c [Pa] (> 0): each contact's normal stiffness per unit area is E_c / d, d "
        "the distance of the two disk centres (docs/voronoi.md, 'Contact stiffness'); "
        "with stiffness ratio 1 the network of rigid grains has E = E_c, nu = 0");
    prm.declare_entry("stiffness ratio", "1.5", Patterns::Double(),
                      "kappa = k_n / k_s (> 0); kappa > 1 gives nu > 0 and E < E_c");
    prm.declare_entry("tensile strength", "2.5e6", Patterns::Double(),
                      "sigma_t of the contact points [Pa] (>= 0)");
    prm.declare_entry("cohesion", "7.5e6", Patterns::Double(),
                      "c of the contact points [Pa] (>= 0)");
    prm.declare_entry("friction", "0.5", Patterns::Double(),
                      "mu, friction coefficient of the contact points (>= 0)");
    prm.declare_entry(
        "tensile fracture energy", "1", Patterns::Double(),
        "G_t [J/m^2] (>= 0): the energy of the tensile softening branch; 0: the brittle "
        "value sigma_t^2 d / (2 E_c) of each contact, and a positive value must be at "
        "least that for every contact");
    prm.declare_entry(
        "shear fracture energy", "10", Patterns::Double(),
        "G_s [J/m^2] (>= 0): the energy of the cohesion's softening; 0: the brittle "
        "value c^2 kappa d / (2 E_c) of each contact, and a positive value must be at "
        "least that for every contact");
    prm.declare_entry("contact points", "lobatto",
                      Patterns::Selection("lobatto|reference point"),
                      "lobatto: three points per cell edge (ends and middle, areas "
                      "1/6, 2/3, 1/6); reference point: one point (the point contact)");
    prm.declare_entry("time step safety", "0.5", Patterns::Double(),
                      "time step = this x the stable estimate, in (0, 1]");
    prm.declare_entry("grain youngs modulus", "100e9", Patterns::Double(),
                      "flexible-voronoi: E of the grains [Pa] (> 0, plane strain)");
    prm.declare_entry("grain poisson ratio", "0.2", Patterns::Double(),
                      "flexible-voronoi: nu of the grains, in [0, 0.5)");
    prm.declare_entry(
        "short edge fraction", "0.1", Patterns::Double(),
        "flexible-voronoi: cell vertices closer than this fraction of the mean "
        "equivalent cell diameter share one mesh node, in [0, 0.5) (0: the full "
        "centroid fan; a short edge's sliver triangle would cut the time step, "
        "docs/voronoi.md 'Short cell edges')");
    prm.leave_subsection();
  }

  VoronoiCalibrateSettings read_voronoi_settings(ParameterHandler  &prm,
                                                 const std::string &where, bool fit)
  {
    VoronoiCalibrateSettings s;
    s.where = where;
    prm.enter_subsection("Material");
    const std::string type = prm.get("type");
    prm.leave_subsection();
    s.flexible    = type == "flexible-voronoi";
    s.fit.enabled = fit;

    prm.enter_subsection("Problem");
    if (prm.get_integer("dimension") != 2)
      refuse(where, "Material/type = " + type +
                        " needs Problem/dimension = 2 (Voronoi grains are 2D; allowed "
                        "in 3D: linear, contactbonded, parallelbonded, flatjointed)");
    s.out = prm.get("output directory");
    s.vtk = prm.get_bool("vtk");
    if (prm.get_integer("seeds") != 1)
      refuse(where, "Problem/seeds = " + std::to_string(prm.get_integer("seeds")) +
                        ": the Voronoi calibration runs one packing (allowed: 1)");
    prm.leave_subsection();
    if (s.out.empty())
      refuse(where, "Problem/output directory must not be empty");

    auto &sp = s.specimen;
    auto &c  = s.contact;
    auto &l  = s.lab;
    prm.enter_subsection("Material");
    read_sizes(prm.get("size distribution"), where, sp);
    sp.n_grains = prm.get_double("number of grains");
    check(where, "Material/number of grains", sp.n_grains, 10, 1e6);
    s.density = prm.get_double("density");
    check(where, "Material/density", s.density, 0, HUGE_VAL, true);
    if (prm.get_bool("bulk density"))
      refuse(where, "Material/bulk density: Voronoi cells fill the specimen, the grain "
                    "density is the bulk density (allowed: false)");
    l.damping = prm.get_double("local damping");
    check(where, "Material/local damping", l.damping, 0, 1, false, true);
    sp.seed = prm.get_integer("seed");
    prm.enter_subsection("Voronoi");
    const std::string v       = "Material/Voronoi/";
    c.contact_modulus         = prm.get_double("contact modulus");
    c.kratio                  = prm.get_double("stiffness ratio");
    c.tensile_strength        = prm.get_double("tensile strength");
    c.cohesion                = prm.get_double("cohesion");
    c.friction                = prm.get_double("friction");
    c.tensile_fracture_energy = prm.get_double("tensile fracture energy");
    c.shear_fracture_energy   = prm.get_double("shear fracture energy");
    check(where, v + "contact modulus", c.contact_modulus, 0, HUGE_VAL, true, true);
    check(where, v + "stiffness ratio", c.kratio, 0, HUGE_VAL, true, true);
    check(where, v + "tensile strength", c.tensile_strength, 0, HUGE_VAL, false, true);
    check(where, v + "cohesion", c.cohesion, 0, HUGE_VAL, false, true);
    check(where, v + "friction", c.friction, 0, HUGE_VAL, false, true);
    check(where, v + "tensile fracture energy", c.tensile_fracture_energy, 0, HUGE_VAL,
          false, true);
    check(where, v + "shear fracture energy", c.shear_fracture_energy, 0, HUGE_VAL, false,
          true);
    l.scheme = prm.get("contact points") == "lobatto" ? vor::PointScheme::lobatto3
                                                      : vor::PointScheme::reference_point;
    l.safety = prm.get_double("time step safety");
    check(where, v + "time step safety", l.safety, 0, 1, true);
    if (s.flexible)
      {
        s.grain.youngs_modulus = prm.get_double("grain youngs modulus");
        s.grain.poisson_ratio  = prm.get_double("grain poisson ratio");
        check(where, v + "grain youngs modulus", s.grain.youngs_modulus, 0, HUGE_VAL,
              true, true);
        check(where, v + "grain poisson ratio", s.grain.poisson_ratio, 0, 0.5, false,
              true);
        l.flexible_mesh.min_edge_fraction = prm.get_double("short edge fraction");
        check(where, v + "short edge fraction", l.flexible_mesh.min_edge_fraction, 0, 0.5,
              false, true);
        s.grain.density   = s.density;
        s.grain.thickness = c.thickness;
      }
    prm.leave_subsection();
    prm.leave_subsection();

    prm.enter_subsection("Vessel");
    if (prm.get("shape") != "box")
      refuse(where, "Vessel/shape: Voronoi grains fill a rectangle (allowed: box)");
    sp.height = prm.get_double("height");
    sp.width  = prm.get_double("width");
    check(where, "Vessel/height", sp.height, 0, HUGE_VAL, true);
    check(where, "Vessel/width", sp.width, 0, HUGE_VAL, true);
    prm.leave_subsection();

    prm.enter_subsection("Packing");
    sp.packing_pressure = prm.get_double("material pressure");
    check(where, "Packing/material pressure", sp.packing_pressure, 0, HUGE_VAL, true);
    prm.leave_subsection();

    prm.enter_subsection("Joint");
    if (prm.get_bool("enabled"))
      refuse(where, "Joint/enabled: the smooth-jointed interface is a disk-contact law, "
                    "not available for Voronoi grains (allowed: false)");
    prm.leave_subsection();

    prm.enter_subsection("Tests");
    const std::string t = "Tests/";
    l.strain_rate       = prm.get_double("strain rate");
    check(where, t + "strain rate", l.strain_rate, 0, HUGE_VAL, true, true);
    const double Pc = prm.get_double("confining pressure");
    check(where, t + "confining pressure", Pc, 0, HUGE_VAL);
    std::vector<double> series;
    for (const auto &p : Utilities::split_string_list(prm.get("confining pressures")))
      {
        series.push_back(Utilities::string_to_double(p));
        check(where, t + "confining pressures", series.back(), 0, HUGE_VAL);
      }
    l.load_fraction = prm.get_double("load fraction");
    check(where, t + "load fraction", l.load_fraction, 0, 1, true, true);
    l.strain_limit = prm.get_double("strain limit");
    check(where, t + "strain limit", l.strain_limit, 0, 1, true);
    l.step_limit = prm.get_integer("step limit");
    check(where, t + "step limit", double(l.step_limit), 1, HUGE_VAL);
    s.brazilian_platen_friction = prm.get_double("platen friction");
    check(where, t + "platen friction", s.brazilian_platen_friction, 0, HUGE_VAL);
    l.fit_lo = prm.get_double("fit window low");
    l.fit_hi = prm.get_double("fit window high");
    check(where, t + "fit window low", l.fit_lo, 0, 1, false, true);
    check(where, t + "fit window high", l.fit_hi, l.fit_lo, 1, true);
    s.crack_initiation_fraction = prm.get_double("crack initiation fraction");
    check(where, t + "crack initiation fraction", s.crack_initiation_fraction, 0, 1,
          true);
    s.crack_initiation_method =
        dem::parse_crack_initiation_method(prm.get("crack initiation method"));
    s.crack_volumetric_fraction = prm.get_double("crack volumetric strain fraction");
    check(where, t + "crack volumetric strain fraction", s.crack_volumetric_fraction, 0,
          1, true, true);
    l.ratio_limit = prm.get_double("seating ratio limit");
    check(where, t + "seating ratio limit", l.ratio_limit, 0, 1, true);
    if (prm.get_double("brazilian split fraction") != 0.5)
      refuse(where, "Tests/brazilian split fraction: the Brazilian failure-mode check "
                    "is not available for Voronoi grains (allowed: 0.5, the default)");
    if (prm.get_double("brazilian diameter") != 0 ||
        prm.get_double("brazilian thickness") != 0)
      refuse(where,
             "Tests/brazilian diameter, Tests/brazilian thickness: a Brazilian "
             "specimen of its own is not available for Voronoi grains (allowed: 0, "
             "the default: the disk is cut from the specimen)");
    if (prm.get_double("brazilian flat angle") != 0)
      refuse(where, "Tests/brazilian flat angle: the flattened Brazilian disk is not "
                    "available for Voronoi grains (allowed: 0, the round disk)");
    if (prm.get("loading rate check") != "false")
      refuse(where, "Tests/loading rate check: the rate repeats are not available for "
                    "Voronoi grains (allowed: false)");
    for (const auto &name : Utilities::split_string_list(prm.get("tests")))
      {
        auto add = [&](const std::string &label, vor::VoronoiTest kind, double p,
                       bool in_series = false) {
          s.tests.push_back({label, kind, p, in_series});
        };
        if (name == "ucs")
          add(name, vor::VoronoiTest::unconfined_compression, 0);
        else if (name == "triaxial")
          add(name, vor::VoronoiTest::confined_compression, Pc);
        else if (name == "triaxial series")
          {
            if (std::count_if(series.begin(), series.end(),
                              [&](double p) { return p != series[0]; }) == 0)
              refuse(where, "Tests/confining pressures: the series needs at least two "
                            "distinct pressures");
            for (double p : series)
              {
                std::ostringstream label;
                label << "triaxial series " << p / 1e6 << " MPa";
                add(label.str(),
                    p > 0 ? vor::VoronoiTest::confined_compression
                          : vor::VoronoiTest::unconfined_compression,
                    p, true);
              }
          }
        else if (name == "direct tension")
          add(name, vor::VoronoiTest::direct_tension, 0);
        else if (name == "brazilian")
          add(name, vor::VoronoiTest::brazilian, 0);
        else
          refuse(where, "Tests/tests: '" + name +
                            "' is not available for Material/type = " + type +
                            " (allowed: ucs, triaxial, triaxial series, direct tension, "
                            "brazilian)");
      }
    if (s.tests.empty())
      refuse(where, "Tests/tests: no test given");
    prm.leave_subsection();

    // Subsection Fit: the searched keys of Material/Voronoi and bounds that
    // give a material (moduli and kappa > 0, the grains' nu < 0.5).
    prm.enter_subsection("Fit");
    read_fit_settings(prm, where, s.fit, [&](const FitParameter &p) {
      VoronoiCalibrateSettings probe = s;
      voronoi_fit_parameter(probe, p.name, where);
      const std::string what = "Fit/parameters (" + p.name + ")";
      const bool positive = p.name == "contact modulus" || p.name == "stiffness ratio" ||
                            p.name == "grain youngs modulus";
      if (positive && !(p.lo > 0))
        refuse(where, what + ": the lower bound must be > 0");
      if (p.name == "grain poisson ratio" && !(p.hi < 0.5))
        refuse(where, what + ": the upper bound must be < 0.5");
    });
    prm.leave_subsection();
    if (s.fit.enabled)
      for (const auto &t : s.fit.targets)
        if (t.name == "mi" &&
            std::none_of(s.tests.begin(), s.tests.end(),
                         [](const VoronoiTestSpec &x) { return x.in_series; }))
          refuse(where, "Fit/Targets/mi needs 'triaxial series' in Tests/tests (the "
                        "Hoek-Brown fit of its peaks)");

    // The library's own checks (same ranges; any remaining combination).
    c.validate(where + ", subsection Material/Voronoi");
    l.validate(where + ", subsection Tests");
    if (s.flexible)
      s.grain.validate(where + ", subsection Material/Voronoi");
    return s;
  }
} // namespace demfem::apps
