// `demfem tunnel FILE.prm`: the coupled excavation-damage run (issue 5,
// DESIGN §5-6). Every input is validated before the output directory is
// created, so a bad input writes nothing. Exit codes: 0 done, 1 bad input
// or error, 2 the run diverged (diagnosis printed and in summary.json),
// 130 / 143 stopped by SIGINT / SIGTERM after writing a checkpoint.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include "apps/commands.h"
#include "apps/prm_cli.h"
#include "coupling/tunnel_run.h"

#include <csignal>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace demfem::apps
{
  namespace
  {
    using namespace dealii;

    const char *usage =
        "usage: demfem tunnel FILE.prm [--set \"Section/key=value\"]... "
        "[--restart CHECKPOINT.h5] [--print-parameters] [--help]\n"
        "\n"
        "Coupled DEM-continuum tunnel excavation (2D): a bonded-grain region of\n"
        "radius 'DEM region/radius' around the tunnel is embedded in an explicit\n"
        "elastic continuum through a ring of wall facets; in-situ stress ramp,\n"
        "equilibrium, excavation (in stages), equilibrium. Writes summary.json,\n"
        "history.csv, wall_displacement.csv and VTK series (particles, bonds,\n"
        "cracks, continuum; tunnel.pvd opens all) into Problem/output directory.\n"
        "Every 'Output/checkpoint interval' steps (0: never) and at the end it writes\n"
        "checkpoint.h5 there; Ctrl-C (SIGINT) or SIGTERM writes one and stops.\n"
        "--restart continues from a checkpoint written with the same parameters\n"
        "(output directory and checkpoint interval may differ) as if never stopped.\n";

    /// Async-signal-safe: only sets the flag the run polls at step boundaries.
    extern "C" void on_stop_signal(int sig) { coupling::tunnel_stop_requested = sig; }

    void declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Problem");
      prm.declare_entry("dimension", "2", Patterns::Integer(2, 3),
                        "2 = plane strain (3 is not implemented for tunnel yet)");
      prm.declare_entry("output directory", "out/tunnel", Patterns::Anything(),
                        "Directory for summary.json, CSV and VTK files");
      prm.leave_subsection();

      prm.enter_subsection("Tunnel");
      prm.declare_entry("radius", "1.0", Patterns::Double(), "Tunnel radius a [m] (> 0)");
      for (const std::string c : {"xx", "yy", "zz", "xy", "xz", "yz"})
        prm.declare_entry("in situ stress " + c,
                          c == "xx"   ? "-30e6"
                          : c == "yy" ? "-60e6"
                          : c == "zz" ? "-45e6"
                                      : "0",
                          Patterns::Double(),
                          "In-situ stress component " + c +
                              " [Pa], tension positive; z is the tunnel axis (2D uses "
                              "xx, yy, xy)");
      prm.declare_entry("excavation stages", "1", Patterns::Integer(1, 1000),
                        "The forces of the removed grains on the remaining ones are "
                        "relaxed to zero in this many equal stages");
      prm.leave_subsection();

      prm.enter_subsection("Continuum");
      prm.declare_entry(
          "mesh", "generate", Patterns::Anything(),
          "'generate': graded annulus from DEM region/radius to outer radius "
          "(the only choice for the coupled run)");
      prm.declare_entry("outer radius", "30.0", Patterns::Double(),
                        "Far-field radius R [m] (> 2 x DEM region/radius); fixed");
      prm.declare_entry("young modulus", "60e9", Patterns::Double(),
                        "Plane-strain Young's modulus E [Pa] (> 0)");
      prm.declare_entry("poisson ratio", "0.25", Patterns::Double(),
                        "Plane-strain Poisson's ratio, in (-1, 0.5)");
      prm.declare_entry("material file", "", Patterns::Anything(),
                        "JSON with \"E\" and \"nu\" (plane strain; demfem calibrate); "
                        "overrides young modulus and poisson ratio. Empty: the DEM "
                        "region's material file when set");
      prm.declare_entry("element degree", "1", Patterns::Integer(1, 2),
                        "FE_Q degree; the wall-facet coupling needs 1");
      prm.declare_entry("refinements", "0", Patterns::Integer(0, 0),
                        "Global refinements (0: the interface facets are sized from the "
                        "grains)");
      prm.declare_entry("solver", "amg-cg", Patterns::Selection("amg-cg|direct"),
                        "Unused by the explicit scheme (kept for demfem fem files)");
      prm.declare_entry("density", "2650", Patterns::Double(), "Density [kg/m^3] (> 0)");
      prm.leave_subsection();

      prm.enter_subsection("DEM region");
      prm.declare_entry("radius", "4.0", Patterns::Double(),
                        "Outer radius b of the embedded region [m]");
      prm.declare_entry("material file", "", Patterns::Anything(),
                        "material.json of demfem calibrate (microparameters, E, nu); "
                        "empty: the material keys below");
      prm.declare_entry("breakable", "true", Patterns::Bool(),
                        "false: unbreakable bonds (verification)");
      prm.declare_entry("grain diameter", "", Patterns::Anything(),
                        "Optional mean grain diameter [m]; scales the size range");
      prm.declare_entry("grain diameter min", "0.16", Patterns::Double(),
                        "Smallest grain diameter [m] (without material file)");
      prm.declare_entry("grain diameter max", "0.24", Patterns::Double(),
                        "Largest grain diameter [m] (without material file)");
      prm.declare_entry("density", "2650", Patterns::Double(), "Grain density [kg/m^3]");
      prm.declare_entry("emod", "20e9", Patterns::Double(), "Flat-joint E* [Pa]");
      prm.declare_entry("krat", "1.5", Patterns::Double(), "Flat-joint kappa*");
      prm.declare_entry("fric", "0.6", Patterns::Double(), "Flat-joint friction");
      prm.declare_entry("fj ten", "10e6", Patterns::Double(), "Tensile strength [Pa]");
      prm.declare_entry("fj coh", "60e6", Patterns::Double(), "Cohesion [Pa]");
      prm.declare_entry("fj fa", "30", Patterns::Double(), "Friction angle [deg]");
      prm.declare_entry("fj Nr", "2", Patterns::Integer(1, 64), "Elements per joint");
      prm.declare_entry("lnm emod", "20e9", Patterns::Double(),
                        "E* of non-bonded contacts [Pa]");
      prm.declare_entry("lnm krat", "1.5", Patterns::Double(),
                        "kappa* of non-bonded contacts");
      prm.declare_entry("lnm fric", "0.5", Patterns::Double(), "Friction, non-bonded");
      prm.declare_entry("seed", "10000", Patterns::Integer(0), "Packing seed");
      prm.leave_subsection();

      prm.enter_subsection("Coupling");
      prm.declare_entry("variant", "wall-facets",
                        Patterns::Selection("slaved-layer|wall-facets"),
                        "wall-facets (implemented); slaved-layer is not implemented yet");
      prm.declare_entry("scheme", "explicit",
                        Patterns::Selection("explicit|quasi-static"),
                        "explicit (implemented); quasi-static is not implemented yet");
      prm.declare_entry("subcycles", "1", Patterns::Integer(1, 1000),
                        "DEM steps per continuum step");
      prm.declare_entry(
          "timestep safety", "0.8", Patterns::Double(),
          "dt = safety x min(DEM critical, continuum critical / subcycles)");
      prm.declare_entry("relaxation", "1.0", Patterns::Double(),
                        "Relaxation of the quasi-static scheme (unused by explicit)");
      prm.declare_entry("equilibrium ratio", "1e-3", Patterns::Double(),
                        "Equilibrium: unbalanced-force ratio below this");
      prm.declare_entry("ramp steps", "2000", Patterns::Integer(1),
                        "Steps of the in-situ load ramp");
      prm.declare_entry("step limit", "20000", Patterns::Integer(1),
                        "Step limit of each equilibrium phase / excavation stage");
      prm.leave_subsection();

      prm.enter_subsection("Output");
      prm.declare_entry("interval", "1000", Patterns::Integer(0),
                        "Steps between VTK frames (0: phase ends only)");
      prm.declare_entry("checkpoint interval", "20000", Patterns::Integer(0),
                        "Steps between checkpoints (HDF5 checkpoint.h5 in the output "
                        "directory, written atomically); 0: none");
      prm.leave_subsection();
    }

    boost::property_tree::ptree read_json(const std::string &key, const std::string &file)
    {
      AssertThrow(std::filesystem::is_regular_file(file),
                  ExcMessage(key + ": '" + file + "' does not exist"));
      boost::property_tree::ptree t;
      try
        {
          boost::property_tree::read_json(file, t);
        }
      catch (const std::exception &e)
        {
          AssertThrow(
              false, ExcMessage(key + ": '" + file + "' is not valid JSON: " + e.what()));
        }
      return t;
    }

    coupling::TunnelParams read_settings(ParameterHandler &prm)
    {
      coupling::TunnelParams s;
      prm.enter_subsection("Problem");
      AssertThrow(
          prm.get_integer("dimension") == 2,
          ExcMessage("Problem/dimension: the coupled tunnel run is implemented for 2 "
                     "only (3D slab / tunnel section: not done yet)"));
      s.output_directory = prm.get("output directory");
      prm.leave_subsection();

      prm.enter_subsection("Tunnel");
      s.tunnel_radius = prm.get_double("radius");
      s.sigma0 << prm.get_double("in situ stress xx"),
          prm.get_double("in situ stress xy"), prm.get_double("in situ stress xy"),
          prm.get_double("in situ stress yy");
      s.stages = prm.get_integer("excavation stages");
      prm.leave_subsection();

      prm.enter_subsection("Continuum");
      AssertThrow(
          prm.get("mesh") == "generate",
          ExcMessage("Continuum/mesh: the coupled run generates its mesh around the "
                     "DEM region; only 'generate' is allowed"));
      s.continuum.outer_radius  = prm.get_double("outer radius");
      s.continuum.young_modulus = prm.get_double("young modulus");
      s.continuum.poisson_ratio = prm.get_double("poisson ratio");
      s.continuum.density       = prm.get_double("density");
      std::string cmat          = prm.get("material file");
      AssertThrow(prm.get_integer("element degree") == 1,
                  ExcMessage("Continuum/element degree: the wall-facet coupling needs 1 "
                             "(facet vertices are the element nodes)"));
      prm.leave_subsection();

      prm.enter_subsection("DEM region");
      auto &r         = s.region;
      r.radius        = prm.get_double("radius");
      const auto dmat = prm.get("material file");
      r.breakable     = prm.get_bool("breakable");
      const auto gd   = prm.get("grain diameter");
      r.d_lo          = prm.get_double("grain diameter min");
      r.d_hi          = prm.get_double("grain diameter max");
      r.density       = prm.get_double("density");
      r.emod          = prm.get_double("emod");
      r.krat          = prm.get_double("krat");
      r.fric          = prm.get_double("fric");
      r.fj_ten        = prm.get_double("fj ten");
      r.fj_coh        = prm.get_double("fj coh");
      r.fj_fa         = prm.get_double("fj fa");
      r.fj_Nr         = prm.get_integer("fj Nr");
      r.lnm_emod      = prm.get_double("lnm emod");
      r.lnm_krat      = prm.get_double("lnm krat");
      r.lnm_fric      = prm.get_double("lnm fric");
      r.seed          = prm.get_integer("seed");
      prm.leave_subsection();
      if (!dmat.empty())
        {
          const auto t = read_json("DEM region/material file", dmat);
          try
            {
              AssertThrow(t.get<int>("dim") == 2,
                          ExcMessage("DEM region/material file '" + dmat +
                                     "': incompatible dimension " +
                                     t.get<std::string>("dim") +
                                     " (the tunnel run is 2D)"));
              const auto &m = t.get_child("microparameters");
              AssertThrow(m.get<std::string>("type", "flatjointed") == "flatjointed",
                          ExcMessage("DEM region/material file '" + dmat +
                                     "': only flat-jointed materials are supported"));
              const auto  &p0   = m.get_child("size_distribution").begin()->second;
              const double mult = m.get<double>("diameter_multiplier", 1.0);
              r.d_lo            = mult * p0.get<double>("D_lo_m");
              r.d_hi            = mult * p0.get<double>("D_hi_m");
              r.density         = m.get<double>("density_kg_m3");
              r.damping         = m.get<double>("local_damping", r.damping);
              r.seed            = m.get<double>("seed", double(r.seed));
              r.lnm_emod        = m.get<double>("lnm_emod_Pa");
              r.lnm_krat        = m.get<double>("lnm_krat");
              r.lnm_fric        = m.get<double>("lnm_fric");
              r.emod            = m.get<double>("emod_Pa");
              r.krat            = m.get<double>("krat");
              r.fric            = m.get<double>("fric");
              r.igap            = m.get<double>("igap_m", 0.0);
              r.fj_Nr           = m.get<int>("fj_Nr");
              r.fj_ten          = m.get<double>("fj_ten_mean_Pa");
              r.fj_coh          = m.get<double>("fj_coh_mean_Pa");
              r.fj_fa           = m.get<double>("fj_fa_deg");
            }
          catch (const boost::property_tree::ptree_error &e)
            {
              AssertThrow(false, ExcMessage("DEM region/material file '" + dmat +
                                            "': missing or bad key: " + e.what()));
            }
          if (cmat.empty())
            cmat = dmat;
        }
      if (!gd.empty())
        {
          double d = 0;
          try
            {
              d = std::stod(gd);
            }
          catch (...)
            {
              d = -1;
            }
          AssertThrow(d > 0, ExcMessage("DEM region/grain diameter: '" + gd +
                                        "' is not a positive number [m]"));
          const double k = d / r.mean_diameter();
          r.d_lo *= k;
          r.d_hi *= k;
        }
      if (!cmat.empty())
        {
          const auto t = read_json("Continuum/material file", cmat);
          try
            {
              s.continuum.young_modulus = t.get<double>("E");
              s.continuum.poisson_ratio = t.get<double>("nu");
            }
          catch (const boost::property_tree::ptree_error &e)
            {
              AssertThrow(false,
                          ExcMessage("Continuum/material file '" + cmat +
                                     "': need numeric \"E\" and \"nu\": " + e.what()));
            }
        }

      prm.enter_subsection("Coupling");
      AssertThrow(
          prm.get("variant") == "wall-facets",
          ExcMessage("Coupling/variant: 'slaved-layer' is not implemented yet; use "
                     "'wall-facets'"));
      AssertThrow(
          prm.get("scheme") == "explicit",
          ExcMessage("Coupling/scheme: 'quasi-static' is not implemented yet; use "
                     "'explicit'"));
      s.coupling.subcycles = prm.get_integer("subcycles");
      s.coupling.safety    = prm.get_double("timestep safety");
      s.ratio_tolerance    = prm.get_double("equilibrium ratio");
      s.ramp_steps         = prm.get_integer("ramp steps");
      s.phase_step_limit   = prm.get_integer("step limit");
      AssertThrow(s.ratio_tolerance > 0,
                  ExcMessage("Coupling/equilibrium ratio must be > 0"));
      prm.leave_subsection();
      prm.enter_subsection("Output");
      s.vtk_interval        = prm.get_integer("interval");
      s.checkpoint_interval = prm.get_integer("checkpoint interval");
      prm.leave_subsection();
      s.validate("parameter file"); // throws dem::InputError naming the key
      return s;
    }

  } // namespace

  int run_tunnel(int argc, char **argv)
  {
    Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    try
      {
        std::string      file, restart;
        ParameterHandler prm;
        declare_parameters(prm);
        // --restart FILE is ours; the rest is the shared .prm command line.
        std::vector<char *> args;
        for (int i = 0; i < argc; ++i)
          if (std::string(argv[i]) == "--restart")
            {
              AssertThrow(i + 1 < argc,
                          ExcMessage("--restart needs a checkpoint file name"));
              restart = argv[++i];
            }
          else
            args.push_back(argv[i]);
        args.push_back(nullptr);
        switch (read_parameters(int(args.size()) - 1, args.data(), prm, usage, file))
          {
          case PrmAction::help:
            std::cout << usage;
            return 0;
          case PrmAction::print:
            prm.print_parameters(std::cout, ParameterHandler::Text);
            return 0;
          case PrmAction::run:
            break;
          }
        coupling::TunnelParams s = read_settings(prm);
        {
          std::ostringstream text; // the parameters after --set overrides
          prm.print_parameters(text, ParameterHandler::ShortPRM);
          s.prm_text = text.str();
        }
        s.restart_file = restart;
        std::signal(SIGINT, on_stop_signal);
        std::signal(SIGTERM, on_stop_signal);
        const auto r = coupling::run_tunnel(s, std::cout);
        if (r.interrupted)
          {
            const int sig = coupling::tunnel_stop_requested;
            std::cout << "demfem tunnel: stopped at step " << r.steps
                      << " on request; continue with: demfem tunnel " << file
                      << " --restart " << r.checkpoint << std::endl;
            return sig == SIGTERM ? 143 : 130;
          }
        if (r.diverged)
          {
            std::cerr << "demfem tunnel: the run diverged: " << r.diagnosis
                      << "\n(summary.json records it; no non-finite value was written)"
                      << std::endl;
            return 2;
          }
        std::cout << "demfem tunnel: done in " << r.wall_time_s << " s: " << r.n_particles
                  << " grains, " << r.cracks_total << " cracks (" << r.cracks_tensile
                  << " tensile), damage-zone depth " << r.damage_zone_depth
                  << " m, mean wall convergence " << r.wall_convergence_mean
                  << " m, interface force imbalance " << r.interface_force_imbalance_max
                  << "; output in " << s.output_directory << std::endl;
        return 0;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem tunnel: error: " << exception_text(e) << std::endl;
        return 1;
      }
  }
} // namespace demfem::apps
