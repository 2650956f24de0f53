// `demfem tunnel FILE.prm`: the coupled excavation-damage run
// (docs/architecture.md, "Coupling" and "Outputs and run status"). Every input
// is validated before the output directory is created, so a bad input writes
// nothing. The run's outcome is checked before it says "ok"
// (coupling/tunnel_result.h); every other status has its own non-zero exit
// code (docs/tunnel.md, "Run status and exit codes").
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/prm_cli.h"
#include "apps/study.h"
#include "apps/tunnel_probe.h"
#include "coupling/tunnel_run.h"

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
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
        "[--restart CHECKPOINT.h5] [--accept STATUS[,STATUS]] [--probe [--probe-seeds "
        "N]] "
        "[--overwrite] [--defaults] [--print-parameters] [--help]\n"
        "\n"
        "Coupled DEM-continuum tunnel excavation, 2D or (Problem/dimension = 3) a\n"
        "slab 0 < z < 'DEM region/slab thickness' in plane strain through walls,\n"
        "or with 'Continuum/axial extension' > 0 that section surrounded by a 3D\n"
        "continuum reaching that far beyond both ends (tunnel through its length):\n"
        "a bonded-grain region of\n"
        "radius 'DEM region/radius' around the tunnel is embedded in an elastic\n"
        "continuum (Coupling/variant: slaved-layer, the continuum overlapping the\n"
        "region's rim whose grains follow it, or wall-facets, a ring of DEM walls;\n"
        "Coupling/scheme: explicit, quasi-static or condensed, the continuum's\n"
        "static stiffness on the coupling nodes); in-situ stress ramp,\n"
        "equilibrium, excavation (in stages), equilibrium. Writes summary.json,\n"
        "history.csv, wall_displacement.csv and VTK series (particles, bonds,\n"
        "cracks, continuum; tunnel.pvd opens all) into Problem/output directory.\n"
        "Every 'Output/checkpoint interval' steps (0: never) and at the end it writes\n"
        "checkpoint.h5 there; Ctrl-C (SIGINT) or SIGTERM writes one and stops.\n"
        "--restart continues from a checkpoint written with the same parameters\n"
        "(output directory and checkpoint interval may differ) as if never stopped;\n"
        "into the checkpoint's own directory it continues that run's files, into\n"
        "another it starts complete ones there. Checkpoints carry checksums: a\n"
        "damaged one is refused, naming the dataset.\n"
        "The run owns its output directory: a lock (demfem.lock) refuses a second\n"
        "run into it, manifest.json records the command, the parameters, the\n"
        "version and the end status, and a directory holding an earlier run is\n"
        "refused unless --overwrite (docs/tunnel.md).\n"
        "Before it says \"ok\" the run checks its outcome: no divergence (energy\n"
        "balance, kinetic-energy growth, NaN), model time advancing, the in-situ\n"
        "state reached (region stress within 'Tunnel/in situ tolerance' of sigma0),\n"
        "every phase equilibrated (not ended by 'Coupling/step limit') and no\n"
        "crack of the damage zone (the excavation cracks connected to the wall)\n"
        "at the coupling boundary. summary.json 'status' names the most severe\n"
        "failure, 'problems' lists each with its numbers. summary.json also holds\n"
        "the damage zone (depth, sectors, area) and, with a material file, how its\n"
        "cracks lie against the elastic zones where sigma1 - sigma3 reaches the\n"
        "material's crack-initiation stresses (docs/tunnel.md, \"Damage measures\").\n"
        "Exit codes: 0 ok, 1 bad input or error, 2 diverged, 3 not_equilibrated,\n"
        "4 in_situ_not_reached, 5 region_too_small, 6 time_not_advancing,\n"
        "130 / 143 stopped by SIGINT / SIGTERM after writing a checkpoint.\n"
        "\n"
        "options:\n"
        "  --restart CHECKPOINT.h5  continue from a checkpoint\n"
        "  --accept STATUS,...      exit 0 for these statuses (not_equilibrated,\n"
        "                           region_too_small); summary.json still names them\n"
        "  --probe                  no tunnel run: build lab specimens with the\n"
        "                           region's genesis at its grain size and run the\n"
        "                           UCS and Brazilian tests of the calibration; compare\n"
        "                           E, nu (within 5 %), UCS, BTS (seed means within 2\n"
        "                           standard errors of their difference)\n"
        "                           with 'DEM region/material file'; without one the\n"
        "                           keys' material in a UCS test, its E, nu against\n"
        "                           the Continuum's (within 5 %); writes probe.json\n"
        "                           into Problem/output directory; exit 0 pass, 3 fail\n"
        "  --probe-seeds N          packing seeds of the probe (default 3; 1 does not\n"
        "                           judge UCS and BTS)\n";

    /// Async-signal-safe: only sets the flag the run polls at step boundaries.
    extern "C" void on_stop_signal(int sig) { coupling::tunnel_stop_requested = sig; }

    /// The tunnel keys (apps/tunnel_prm.h, shared with `demfem study`) and
    /// the right-sizing keys of the Study subsection, used when
    /// 'DEM region/radius = auto' (right-sizing).
    void declare_parameters(ParameterHandler &prm)
    {
      declare_tunnel_parameters(prm);
      study::declare_study_parameters(prm);
    }

    coupling::TunnelParams read_settings(ParameterHandler &prm, bool &radius_auto)
    {
      coupling::TunnelParams s = read_tunnel_settings(prm);
      radius_auto              = s.region.radius < 0;
      if (radius_auto) // Kirsch pre-analysis (right-sizing)
        {
          prm.enter_subsection("DEM region");
          const std::string material = resolve_input_file(prm.get("material file"));
          prm.leave_subsection();
          const auto st   = study::read_study_settings(prm, material);
          const auto ar   = study::auto_region_radius(s.sigma0, s.tunnel_radius, st.ucs,
                                                      st.damage_fraction, st.margin_grains,
                                                      s.region.mean_diameter());
          s.region.radius = ar.radius;
          std::cout << "demfem tunnel: DEM region/radius = auto: sigma1 - sigma3 >= "
                    << ar.threshold << " Pa reaches r = " << ar.damage_radius
                    << " m; region radius " << ar.radius << " m (" << st.margin_grains
                    << " grains margin)" << std::endl;
        }
      // Throws dem::InputError naming the key; the file is named too.
      const auto &cl = command_line();
      s.validate(cl.file.empty()
                     ? std::string("defaults")
                     : "parameter file '" + cl.file + "'" +
                           (cl.overrides.empty() ? "" : " with --set overrides"));
      return s;
    }

    /// The command that continues this run from `checkpoint`: this command
    /// line (the file and every --set override) without its --restart and
    /// --overwrite (which would delete the checkpoint), plus --restart.
    std::string restart_command(const std::string &checkpoint, const std::string &accept)
    {
      const auto              &cl = command_line();
      std::vector<std::string> a  = {"demfem", "tunnel"};
      for (const auto &x : cl.arguments)
        if (x != "--overwrite")
          a.push_back(x);
      if (!accept.empty())
        {
          a.push_back("--accept");
          a.push_back(accept);
        }
      a.push_back("--restart");
      a.push_back(checkpoint);
      return shell_quoted(a);
    }

    /// Whether `checkpoint` lies in `directory` (a restart that continues
    /// the run's own files).
    bool inside(const std::string &checkpoint, const std::string &directory)
    {
      std::error_code ec;
      const auto      a = std::filesystem::weakly_canonical(
               std::filesystem::absolute(checkpoint).parent_path(), ec);
      const auto b =
          std::filesystem::weakly_canonical(std::filesystem::absolute(directory), ec);
      return a == b;
    }

  } // namespace

  int run_tunnel(int argc, char **argv)
  {
    Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    std::optional<RunDirectory>      run_dir;
    try
      {
        std::string                      file, restart;
        bool                             probe       = false;
        int                              probe_seeds = 3;
        std::vector<coupling::RunStatus> accepted;
        std::string                      accept_text; // as given, for the restart hint
        ParameterHandler                 prm;
        declare_parameters(prm);
        // --restart FILE is ours; the rest is the shared .prm command line.
        std::vector<char *> args;
        for (int i = 0; i < argc; ++i)
          if (std::string(argv[i]) == "--restart")
            {
              AssertThrow(i + 1 < argc,
                          ExcMessage("--restart needs a checkpoint file name"));
              restart = argv[++i];
              AssertThrow(std::filesystem::is_regular_file(restart),
                          ExcMessage("--restart: checkpoint '" + restart +
                                     "' does not exist or is not a file"));
            }
          else if (std::string(argv[i]) == "--probe")
            probe = true;
          else if (std::string(argv[i]) == "--probe-seeds")
            {
              AssertThrow(i + 1 < argc,
                          ExcMessage("--probe-seeds needs a number of seeds (1 .. 100)"));
              const std::string n = argv[++i];
              try
                {
                  std::size_t used = 0;
                  probe_seeds      = std::stoi(n, &used);
                  AssertThrow(used == n.size(), ExcMessage(""));
                }
              catch (...)
                {
                  throw UsageError("--probe-seeds: '" + n +
                                   "' is not a whole number (allowed 1 .. 100)");
                }
            }
          else if (std::string(argv[i]) == "--accept")
            {
              AssertThrow(i + 1 < argc,
                          ExcMessage("--accept needs a status list, e.g. --accept "
                                     "not_equilibrated"));
              accept_text = argv[++i];
              for (const auto &name : split_list("--accept", accept_text))
                {
                  coupling::RunStatus st;
                  try
                    {
                      st = coupling::status_from_name(name);
                    }
                  catch (const std::invalid_argument &e)
                    {
                      throw UsageError(std::string("--accept: ") + e.what());
                    }
                  AssertThrow(st == coupling::RunStatus::not_equilibrated ||
                                  st == coupling::RunStatus::region_too_small,
                              ExcMessage("--accept " + name +
                                         ": only not_equilibrated and region_too_small "
                                         "may be accepted (the others are not results)"));
                  accepted.push_back(st);
                }
            }
          else
            args.push_back(argv[i]);
        args.push_back(nullptr);
        if (answered(read_parameters(int(args.size()) - 1, args.data(), prm, usage, file),
                     prm, usage, &std::cout))
          return 0;
        bool                   radius_auto = false;
        coupling::TunnelParams s           = read_settings(prm, radius_auto);
        {
          std::ostringstream text; // the parameters after --set overrides
          prm.print_parameters(text, ParameterHandler::ShortPRM);
          s.prm_text = text.str();
        }
        if (probe)
          {
            prm.enter_subsection("DEM region");
            const std::string material = resolve_input_file(prm.get("material file"));
            prm.leave_subsection();
            std::filesystem::create_directories(s.output_directory);
            const bool pass =
                run_probe(s, material, probe_seeds, s.output_directory, std::cout);
            return pass ? 0 : 3;
          }
        s.restart_file = restart;
        // A foreign checkpoint is bad input: refused before anything is written.
        coupling::check_restart(s);
        claim_output_directory(run_dir, s.output_directory, prm,
                               !restart.empty() && inside(restart, s.output_directory));
        if (radius_auto && run_dir)
          run_dir->resolved("DEM region/radius", s.region.radius);
        std::signal(SIGINT, on_stop_signal);
        std::signal(SIGTERM, on_stop_signal);
        const auto r = coupling::run_tunnel(s, std::cout);
        if (r.interrupted)
          {
            const int sig = coupling::tunnel_stop_requested;
            std::cout << "demfem tunnel: stopped at step " << r.steps
                      << " on request; continue with: "
                      << restart_command(r.checkpoint, accept_text) << std::endl;
            if (run_dir)
              run_dir->finish("interrupted", sig == SIGTERM ? 143 : 130);
            return sig == SIGTERM ? 143 : 130;
          }
        if (r.diverged)
          std::cerr << "demfem tunnel: the run diverged: " << r.diagnosis
                    << "\n(summary.json records it; no non-finite value was written)"
                    << std::endl;
        else
          std::cout << "demfem tunnel: done in " << r.wall_time_s
                    << " s: " << r.n_particles << " grains, " << r.cracks_total
                    << " cracks (" << r.cracks_tensile << " tensile), damage-zone depth "
                    << r.damage_zone_depth << " m, mean wall convergence "
                    << r.wall_convergence_mean << " m, interface force imbalance "
                    << r.interface_force_imbalance_max << "; output in "
                    << s.output_directory << std::endl;
        // Where the damage zone lies against the elastic prediction
        // (summary.json elastic_initiation_zones).
        for (const auto &z : r.initiation_zones)
          {
            std::cout << "demfem tunnel: " << z.zone_cracks_inside << " of the "
                      << z.zone_cracks << " damage-zone cracks (" << z.cracks_inside
                      << " of all " << z.cracks
                      << " excavation cracks) lie where the elastic sigma1 - sigma3 "
                         "reaches the material's "
                      << z.name << " (" << z.threshold / 1e6 << " MPa; ";
            if (z.far_field_exceeds)
              std::cout << "the in-situ stress already does";
            else
              std::cout << "a zone " << z.depth << " m deep";
            std::cout << ")" << std::endl;
          }
        for (const auto &[status, what] : r.problems)
          if (status != coupling::RunStatus::diverged)
            std::cerr << "demfem tunnel: " << coupling::status_name(status) << ": "
                      << what << std::endl;
        const std::string name = coupling::status_name(r.status);
        int               code = coupling::exit_code(r.status);
        if (code != 0 &&
            std::all_of(r.problems.begin(), r.problems.end(), [&](const auto &pr) {
              return std::find(accepted.begin(), accepted.end(), pr.first) !=
                     accepted.end();
            }))
          {
            std::cout << "demfem tunnel: status " << name << " accepted (--accept)"
                      << std::endl;
            code = 0;
          }
        else if (code != 0)
          std::cerr << "demfem tunnel: status " << name << " (exit " << code
                    << "; summary.json lists the problems)" << std::endl;
        if (run_dir)
          run_dir->finish(name, code);
        return code;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem tunnel: error: " << exception_text(e) << std::endl;
        if (run_dir)
          run_dir->finish("error: " + exception_text(e), 1);
        return 1;
      }
  }
} // namespace demfem::apps
