// `demfem fem FILE.prm`: continuum-only run (e.g. the Kirsch hole). Every
// input is validated before the output directory is created, so a bad input
// writes nothing.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/prm_cli.h"
#include "dem/specimen/material_file.h"
#include "fem/elastic_problem.h"

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
        "usage: demfem fem FILE.prm [--set \"Section/key=value\"]... "
        "[--overwrite] [--defaults] [--print-parameters] [--help]\n"
        "\n"
        "Linear elastic continuum around a circular tunnel (dim 2: plane strain,\n"
        "dim 3: slab or 3D mesh). In-situ stress (tension positive, Pa) is released\n"
        "on the tunnel wall (boundary id 3); the far field (id 1) keeps its traction.\n"
        "Writes summary.json, wall_displacement.csv (excavation-induced),\n"
        "wall_stress.csv (total stress) and solution.pvd (+ .pvtu/.vtu) into\n"
        "Problem/output directory, which the run owns (demfem.lock, manifest.json;\n"
        "an earlier run's results there are refused unless --overwrite,\n"
        "docs/tunnel.md). Run with mpirun -np N for a distributed solve.\n"
        "\n"
        "options:\n";

    void declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Problem");
      prm.declare_entry("dimension", "2", Patterns::Integer(2, 3),
                        "2 = plane strain, 3 = full 3D");
      prm.declare_entry("output directory", "out/fem", Patterns::Anything(),
                        "Directory for summary.json, CSV and VTK files");
      prm.leave_subsection();

      prm.enter_subsection("Tunnel");
      prm.declare_entry("radius", "1.0", Patterns::Double(), "Tunnel radius a [m] (> 0)");
      declare_in_situ_stress(prm);
      prm.declare_entry("excavation stages", "1", Patterns::Integer(1, 1000),
                        "The wall traction is released in this many equal "
                        "steps; one VTK output per stage");
      prm.leave_subsection();

      prm.enter_subsection("Continuum");
      prm.declare_entry("mesh", "generate", Patterns::Anything(),
                        "'generate' (graded annulus, extruded slab in 3D) or a "
                        "Gmsh .msh path with boundary ids 1 (far field) and 3 "
                        "(tunnel wall); 3D: id 4 = roller faces (u_z = 0)");
      prm.declare_entry("outer radius", "30.0", Patterns::Double(),
                        "Far-field radius R [m] of the generated mesh (> radius)");
      prm.declare_entry("young modulus", "69e9", Patterns::Double(),
                        "Young's modulus E [Pa] (> 0)");
      prm.declare_entry("poisson ratio", "0.26", Patterns::Double(),
                        "Poisson's ratio nu, in (-1, 0.5)");
      prm.declare_entry("material file", "", Patterns::Anything(),
                        "Optional JSON file with keys \"E\" [Pa] and \"nu\" (e.g. "
                        "written by demfem calibrate); when set it overrides "
                        "young modulus and poisson ratio");
      prm.declare_entry("element degree", "2", Patterns::Integer(1, 2),
                        "Polynomial degree of FE_Q");
      prm.declare_entry("refinements", "0", Patterns::Integer(0, 8),
                        "Global refinements of the mesh");
      prm.declare_entry("solver", "amg-cg", Patterns::Selection("amg-cg|direct"),
                        "AMG-preconditioned CG, or a direct solver (small problems)");
      prm.leave_subsection();
    }

    fem::ElasticSettings read_settings(ParameterHandler &prm)
    {
      fem::ElasticSettings s;
      prm.enter_subsection("Problem");
      s.dimension        = prm.get_integer("dimension");
      s.output_directory = prm.get("output directory");
      prm.leave_subsection();
      prm.enter_subsection("Tunnel");
      s.radius            = prm.get_double("radius");
      s.sxx               = prm.get_double("in situ stress xx");
      s.syy               = prm.get_double("in situ stress yy");
      s.szz               = prm.get_double("in situ stress zz");
      s.sxy               = prm.get_double("in situ stress xy");
      s.sxz               = prm.get_double("in situ stress xz");
      s.syz               = prm.get_double("in situ stress yz");
      s.excavation_stages = prm.get_integer("excavation stages");
      prm.leave_subsection();
      prm.enter_subsection("Continuum");
      s.mesh                     = prm.get("mesh");
      s.outer_radius             = prm.get_double("outer radius");
      s.young_modulus            = prm.get_double("young modulus");
      s.poisson_ratio            = prm.get_double("poisson ratio");
      const std::string material = resolve_input_file(prm.get("material file"));
      s.degree                   = prm.get_integer("element degree");
      s.refinements              = prm.get_integer("refinements");
      s.solver                   = prm.get("solver");
      prm.leave_subsection();

      if (!material.empty())
        {
          AssertThrow(
              std::filesystem::is_regular_file(material),
              ExcMessage("Continuum/material file: '" + material + "' does not exist"));
          // Errors name the material file and its key (dem/specimen/material_file.h).
          s.young_modulus = dem::read_material_number(material, "E");
          s.poisson_ratio = dem::read_material_number(material, "nu");
        }
      if (s.mesh != "generate")
        AssertThrow(std::filesystem::is_regular_file(s.mesh),
                    ExcMessage("Continuum/mesh: file '" + s.mesh + "' does not exist"));
      return s;
    }

  } // namespace

  int run_fem(int argc, char **argv)
  {
    Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    const MPI_Comm                   comm = MPI_COMM_WORLD;
    std::optional<RunDirectory>      run_dir;
    try
      {
        std::string      file;
        ParameterHandler prm;
        declare_parameters(prm);
        if (answered(read_parameters(argc, argv, prm, usage, file), prm, usage,
                     Utilities::MPI::this_mpi_process(comm) == 0 ? &std::cout : nullptr))
          return 0;

        const fem::ElasticSettings settings = read_settings(prm);
        // One owner per directory: rank 0 claims it for all ranks.
        claim_output_directory(run_dir, settings.output_directory, prm);
        if (settings.dimension == 2)
          {
            fem::ElasticProblem<2> problem(settings, comm);
            problem.run();
          }
        else
          {
            fem::ElasticProblem<3> problem(settings, comm);
            problem.run();
          }
        if (run_dir)
          run_dir->finish("ok", 0);
        return 0;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem fem: error: " << exception_text(e) << std::endl;
        if (run_dir)
          run_dir->finish("error: " + exception_text(e), 1);
        return 1;
      }
  }
} // namespace demfem::apps
