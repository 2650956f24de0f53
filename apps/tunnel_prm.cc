// The parameters of `demfem tunnel` (apps/tunnel_prm.h).
#include "apps/tunnel_prm.h"

#include <deal.II/base/exceptions.h>

#include "apps/cli.h"
#include "apps/prm_cli.h"
#include "dem/specimen/material_file.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace demfem::apps
{
  using namespace dealii;

  namespace
  {
    /// 'DEM region/radius': a positive number [m] or 'auto'.
    double parse_radius(const std::string &v)
    {
      if (v == "auto")
        return -1;
      try
        {
          return parse_number(key_name("DEM region/radius"), v, 1e-300,
                              std::numeric_limits<double>::max(), "m");
        }
      catch (const UsageError &e)
        {
          throw UsageError(std::string(e.what()) + "; or 'auto'");
        }
    }

  } // namespace

  void check_material_file(const std::string &key, const std::string &file)
  {
    AssertThrow(
        std::filesystem::is_regular_file(file),
        ExcMessage(key_name(key) + ": material file '" + file + "' does not exist"));
  }

  void declare_tunnel_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Problem");
    prm.declare_entry("dimension", "2", Patterns::Integer(2, 3),
                      "2 = plane strain; 3 = a slab of the same problem, 0 < z < DEM "
                      "region/slab thickness, plane strain through walls (demfem tunnel "
                      "only)");
    prm.declare_entry("output directory", "out/tunnel", Patterns::Anything(),
                      "Directory for summary.json, CSV and VTK files");
    prm.leave_subsection();

    prm.enter_subsection("Tunnel");
    prm.declare_entry("radius", "1.0", Patterns::Double(), "Tunnel radius a [m] (> 0)");
    declare_in_situ_stress(prm);
    prm.declare_entry("excavation stages", "1", Patterns::Integer(1, 1000),
                      "The forces of the removed grains on the remaining ones are "
                      "relaxed to zero in this many equal stages");
    prm.declare_entry("in situ tolerance", "0.02", Patterns::Double(),
                      "The in-situ state counts as reached when the DEM region's "
                      "centre-disk stress before excavation is within this fraction of "
                      "the largest |in situ stress principal| (every component), in "
                      "(0, 1]; else the run ends with status in_situ_not_reached");
    prm.declare_entry("in situ servo tolerance", "0.005", Patterns::Double(),
                      "Stress-controlled end of the in-situ installation: with the "
                      "continuum held at sigma0, the DEM region's boundary is moved "
                      "(an interface strain, the region's eigenstrain against the "
                      "continuum) until its centre-disk stress is within this "
                      "fraction of sigma0 (the in situ tolerance's measure), then the "
                      "continuum is released; in [0, in situ tolerance), 0: off. Only "
                      "with the slaved layer and the explicit scheme, or the condensed "
                      "scheme (docs/tunnel.md, "
                      "\"In-situ stress servo\")");
    prm.declare_entry("damage link length", "2", Patterns::Double(),
                      "Link length L of the damage zone in mean grain diameters of the "
                      "region, in [1, 10]: an excavation crack belongs to the zone "
                      "when it lies within L of the wall or of a crack of the zone "
                      "(docs/tunnel.md, \"Damage measures\"); summary.json also "
                      "gives the depth at 1.5 L and 2 L");
    prm.leave_subsection();

    prm.enter_subsection("Continuum");
    prm.declare_entry("mesh", "generate", Patterns::Anything(),
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
    prm.declare_entry("mass scaling", "1", Patterns::Anything(),
                      "Density scaling factor of the continuum, in (0, 1e6] (1: its "
                      "physical density); its static response does not depend on it. "
                      "auto (explicit scheme): the "
                      "lightest continuum whose coupled critical step still admits "
                      "the DEM's (at most 1), so that the continuum settles in as few "
                      "DEM steps as the grains (docs/tunnel.md, \"Where the steps go\")");
    prm.declare_entry(
        "axial extension", "0", Patterns::Double(),
        "3D only: length L [m] of continuum beyond each end of the DEM "
        "section (>= 0). 0: the plane-strain slab (DEM between walls z = 0, "
        "t). > 0: a tunnel section in a 3D continuum that surrounds it on "
        "every side, with the tunnel through its whole length (slaved-layer "
        "variant, explicit scheme)");
    prm.leave_subsection();

    prm.enter_subsection("DEM region");
    prm.declare_entry("radius", "4.0", Patterns::Anything(),
                      "Outer radius b of the embedded region [m], or 'auto': "
                      "right-sized by the Kirsch pre-analysis (Study/damage ...)");
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
    prm.declare_entry("fj Nr", "2", Patterns::Integer(1, 64),
                      "Elements per joint (3D: radially)");
    prm.declare_entry("fj Nal", "4", Patterns::Integer(3, 64),
                      "3D: flat-joint elements circumferentially (memo §1.4)");
    prm.declare_entry("slab thickness", "4", Patterns::Double(),
                      "3D: thickness t of the slab (0 < z < t) in mean grain diameters, "
                      ">= 2 largest grains; the DEM slab lies between fixed frictionless "
                      "walls z = 0, t and the continuum's z faces are on rollers. With "
                      "Continuum/axial extension > 0 the length of the DEM section, >= 2 "
                      "overlaps + 1 largest grain");
    prm.declare_entry("memory limit", "auto", Patterns::Anything(),
                      "Refuse a region whose estimated memory exceeds this [GB]; auto: "
                      "half the machine's memory");
    prm.declare_entry("material pressure", "auto", Patterns::Anything(),
                      "Without material file: material pressure Pm [Pa] of the "
                      "genesis that packs the keys' material (fistPkg 4.2.1), > 0; "
                      "auto: lnm emod / 800 (mean grain overlap about 0.25 % of the "
                      "radius)");
    prm.declare_entry("lnm emod", "20e9", Patterns::Double(),
                      "E* of non-bonded contacts [Pa]");
    prm.declare_entry("lnm krat", "1.5", Patterns::Double(),
                      "kappa* of non-bonded contacts");
    prm.declare_entry("lnm fric", "0.5", Patterns::Double(), "Friction, non-bonded");
    prm.declare_entry("seed", "material", Patterns::Anything(),
                      "Packing seed, a non-negative integer; material: the material "
                      "file's seed (10000 without a material file)");
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    prm.declare_entry(
        "variant", "slaved-layer", Patterns::Selection("slaved-layer|wall-facets"),
        "slaved-layer: the continuum overlaps the region's rim, whose "
        "grains follow it; wall-facets: the continuum's inner boundary "
        "is a ring of DEM wall facets (docs/architecture.md, docs/tunnel.md)");
    prm.declare_entry("overlap grains", "2", Patterns::Double(),
                      "slaved-layer: width of the overlap of the continuum and the DEM "
                      "region, in mean grain diameters, in [0.5, 10]");
    prm.declare_entry("scheme", "explicit",
                      Patterns::Selection("explicit|quasi-static|condensed"),
                      "explicit: the continuum is stepped every `subcycles` DEM steps; "
                      "quasi-static: its static interface response (precomputed "
                      "flexibility), relaxed every `subcycles` DEM steps (use 200); "
                      "condensed: its static stiffness condensed onto the coupling "
                      "nodes, which are stepped with the grains under local damping "
                      "(no continuum dynamics; use subcycles = 1)");
    prm.declare_entry("subcycles", "1", Patterns::Integer(1, 1000),
                      "DEM steps per continuum step");
    prm.declare_entry("timestep safety", "0.8", Patterns::Double(),
                      "dt = safety x min(DEM critical, continuum critical / subcycles), "
                      "in (0, 1] (beyond 1 the explicit integration is unstable; "
                      "Study/timestep safety factors may exceed 1 to map that limit)");
    prm.declare_entry("relaxation", "0.3", Patterns::Double(),
                      "quasi-static: relaxation omega of the interface displacement, in "
                      "(0, 2); 0.3 with subcycles = 200 (docs/tunnel.md; unused by "
                      "explicit)");
    prm.declare_entry("equilibrium ratio", "1e-3", Patterns::Double(),
                      "Equilibrium: unbalanced-force ratio below this");
    prm.declare_entry("ramp crossing times", "4", Patterns::Double(),
                      "Duration of the in-situ load ramp in crossing times of the DEM "
                      "region, 2 R / sqrt(E* / rho) (R its radius, E* the flat joints' "
                      "effective modulus, rho the grain density): a physical time, the "
                      "same for every time step; in (0, 1000]");
    prm.declare_entry("step limit", "20000", Patterns::Integer(1),
                      "Step limit of each equilibrium phase / excavation stage (the "
                      "cost budget)");
    prm.declare_entry("phase time limit", "0", Patterns::Double(0),
                      "Model time [s] each equilibrium phase / excavation stage may "
                      "take before it is reported not equilibrated (0: none); a "
                      "physical limit, the same for every time step");
    prm.leave_subsection();

    prm.enter_subsection("Output");
    prm.declare_entry("interval", "1000", Patterns::Integer(0),
                      "Steps between VTK frames (0: phase ends only)");
    prm.declare_entry("checkpoint interval", "20000", Patterns::Integer(0),
                      "Steps between checkpoints (HDF5 checkpoint.h5 in the output "
                      "directory, written atomically); 0: none");
    prm.leave_subsection();
  }

  coupling::TunnelParams read_tunnel_settings(ParameterHandler &prm)
  {
    coupling::TunnelParams s;
    prm.enter_subsection("Problem");
    s.dimension        = prm.get_integer("dimension");
    s.output_directory = prm.get("output directory");
    prm.leave_subsection();

    prm.enter_subsection("Tunnel");
    s.tunnel_radius = prm.get_double("radius");
    s.sigma0 << prm.get_double("in situ stress xx"), prm.get_double("in situ stress xy"),
        prm.get_double("in situ stress xy"), prm.get_double("in situ stress yy");
    s.stages                  = prm.get_integer("excavation stages");
    s.in_situ_tolerance       = prm.get_double("in situ tolerance");
    s.in_situ_servo_tolerance = prm.get_double("in situ servo tolerance");
    s.damage_link_diameters   = prm.get_double("damage link length");
    AssertThrow(s.in_situ_tolerance > 0 && s.in_situ_tolerance <= 1,
                ExcMessage(key_name("Tunnel/in situ tolerance") + " = " +
                           prm.get("in situ tolerance") + " is outside (0, 1]"));
    prm.leave_subsection();

    prm.enter_subsection("Continuum");
    AssertThrow(
        prm.get("mesh") == "generate",
        ExcMessage("Continuum/mesh: the coupled run generates its mesh around the "
                   "DEM region; only 'generate' is allowed"));
    s.continuum.outer_radius  = prm.get_double("outer radius");
    s.continuum.young_modulus = prm.get_double("young modulus");
    s.continuum.poisson_ratio = prm.get_double("poisson ratio");
    // Checked here even when a material file replaces them: a bad value in
    // the file is an error, not silently unused.
    AssertThrow(s.continuum.young_modulus > 0,
                ExcMessage(key_name("Continuum/young modulus") + " = " +
                           std::to_string(s.continuum.young_modulus) +
                           " Pa; allowed: > 0"));
    AssertThrow(s.continuum.poisson_ratio > -1 && s.continuum.poisson_ratio < 0.5,
                ExcMessage(key_name("Continuum/poisson ratio") + " = " +
                           std::to_string(s.continuum.poisson_ratio) +
                           "; allowed: (-1, 0.5)"));
    s.continuum.density = prm.get_double("density");
    if (const auto ms = prm.get("mass scaling"); ms != "auto")
      s.continuum.mass_scaling =
          parse_number(key_name("Continuum/mass scaling"), ms, 1e-300, 1e6, "");
    else
      s.continuum.mass_scaling = 0; // automatic
    s.continuum.axial_extension = prm.get_double("axial extension");
    std::string cmat            = resolve_input_file(prm.get("material file"));
    AssertThrow(prm.get_integer("element degree") == 1,
                ExcMessage("Continuum/element degree: the wall-facet coupling needs 1 "
                           "(facet vertices are the element nodes)"));
    prm.leave_subsection();

    prm.enter_subsection("DEM region");
    auto &r                  = s.region;
    r.radius                 = parse_radius(prm.get("radius"));
    const auto dmat          = resolve_input_file(prm.get("material file"));
    r.breakable              = prm.get_bool("breakable");
    const auto gd            = prm.get("grain diameter");
    r.d_lo                   = prm.get_double("grain diameter min");
    r.d_hi                   = prm.get_double("grain diameter max");
    r.density                = prm.get_double("density");
    r.emod                   = prm.get_double("emod");
    r.krat                   = prm.get_double("krat");
    r.fric                   = prm.get_double("fric");
    r.fj_ten                 = prm.get_double("fj ten");
    r.fj_coh                 = prm.get_double("fj coh");
    r.fj_fa                  = prm.get_double("fj fa");
    r.fj_Nr                  = prm.get_integer("fj Nr");
    r.fj_Nal                 = prm.get_integer("fj Nal");
    const double slab_grains = prm.get_double("slab thickness");
    if (const auto pm = prm.get("material pressure"); pm != "auto")
      r.material_pressure =
          parse_number(key_name("DEM region/material pressure"), pm, 1e-300,
                       std::numeric_limits<double>::max(), "Pa");
    r.lnm_emod            = prm.get_double("lnm emod");
    r.lnm_krat            = prm.get_double("lnm krat");
    r.lnm_fric            = prm.get_double("lnm fric");
    const auto seed_text  = prm.get("seed");
    const bool seed_given = seed_text != "material";
    if (seed_given)
      r.seed = parse_integer(key_name("DEM region/seed"), seed_text, 0,
                             std::numeric_limits<long long>::max());
    if (const auto ml = prm.get("memory limit"); ml != "auto")
      r.memory_limit = 1e9 * parse_number(key_name("DEM region/memory limit"), ml, 1e-6,
                                          std::numeric_limits<double>::max(), "GB");
    prm.leave_subsection();
    if (!dmat.empty())
      {
        check_material_file("DEM region/material file", dmat);
        const dem::MaterialFile f = dem::read_material_file(dmat);
        const auto             &m = f.material;
        AssertThrow(f.dim == s.dimension,
                    ExcMessage("material file '" + dmat + "': key 'dim' = " +
                               std::to_string(f.dim) + ": incompatible dimension with " +
                               key_name("Problem/dimension") + " = " +
                               std::to_string(s.dimension)));
        AssertThrow(m.type == "flatjointed",
                    ExcMessage("material file '" + dmat + "': microparameters/type = '" +
                               m.type + "'; only flat-jointed materials are supported"));
        // Size range over every piece (a Gaussian piece: mean +- 2 sd
        // within its truncation): what the coupling reads for the overlap
        // width and the facet length; the genesis draws from the pieces.
        r.d_lo = HUGE_VAL;
        r.d_hi = 0;
        for (const auto &piece : m.sizes)
          {
            const double lo = piece.gaussian
                                  ? std::max(piece.d_lo, piece.mean - 2 * piece.sd)
                                  : piece.d_lo;
            const double hi =
                piece.gaussian
                    ? (piece.d_hi > 0 ? std::min(piece.d_hi, piece.mean + 2 * piece.sd)
                                      : piece.mean + 2 * piece.sd)
                    : piece.d_hi;
            r.d_lo = std::min(r.d_lo, m.diameter_multiplier * lo);
            r.d_hi = std::max(r.d_hi, m.diameter_multiplier * hi);
          }
        r.material = m;
        r.density  = m.density;
        r.damping  = m.local_damping;
        // The material's packing unless another seed was asked for (a
        // seed sweep of tunnel runs packs other realizations of it).
        if (!seed_given)
          r.seed = m.seed;
        r.lnm_emod = m.lnm_emod;
        r.lnm_krat = m.lnm_krat;
        r.lnm_fric = m.lnm_fric;
        r.emod     = m.emod;
        r.krat     = m.krat;
        r.fric     = m.fric;
        r.igap     = m.igap;
        r.fj_Nr    = m.fj_Nr;
        r.fj_Nal   = m.fj_Nal;
        r.fj_ten   = m.fj_ten.mean;
        r.fj_coh   = m.fj_coh.mean;
        r.fj_fa    = m.fj_fa;
        if (cmat.empty())
          cmat = dmat;
        // The lab's crack-initiation stresses, for the elastic zones the
        // excavation cracks are compared with (coupling/initiation_zone.h);
        // a file without them (older, or no compression test) gives none.
        for (const std::string key : {"crack_initiation", "crack_initiation_crack_count"})
          {
            const double v = dem::read_material_number(dmat, key, false);
            if (std::isnan(v))
              continue;
            AssertThrow(v > 0 && std::isfinite(v),
                        ExcMessage("material file '" + dmat + "': key '" + key +
                                   "' = " + std::to_string(v) + " Pa; must be > 0"));
            s.crack_initiation.emplace_back(key, v);
          }
      }
    if (!gd.empty())
      {
        const double d = parse_number(key_name("DEM region/grain diameter"), gd, 1e-300,
                                      std::numeric_limits<double>::max(), "m");
        r.scale_grains(d / r.mean_diameter());
      }
    // In grain diameters of the final size range; checked (>= 2 largest
    // grains) by RegionParams::validate.
    AssertThrow(slab_grains > 0,
                ExcMessage("DEM region/slab thickness: " + std::to_string(slab_grains) +
                           " mean grain diameters; must be > 0"));
    r.slab_thickness = slab_grains * r.mean_diameter();
    if (!cmat.empty())
      {
        check_material_file("Continuum/material file", cmat);
        s.continuum.young_modulus = dem::read_material_number(cmat, "E");
        s.continuum.poisson_ratio = dem::read_material_number(cmat, "nu");
      }

    prm.enter_subsection("Coupling");
    s.coupling.variant        = prm.get("variant");
    s.coupling.scheme         = prm.get("scheme");
    s.coupling.relaxation     = prm.get_double("relaxation");
    s.coupling.overlap_grains = prm.get_double("overlap grains");
    s.coupling.subcycles      = prm.get_integer("subcycles");
    s.coupling.safety         = prm.get_double("timestep safety");
    // Checked here, where the key enters, before anything runs: the library
    // accepts a safety above 1 so that the study can show divergence
    // (Study/timestep safety factors), a user's run never wants one.
    AssertThrow(s.coupling.safety > 0 && s.coupling.safety <= 1,
                ExcMessage(key_name("Coupling/timestep safety") + " = " +
                           prm.get("timestep safety") +
                           " is outside (0, 1]: above 1 the time step exceeds the "
                           "critical one and the explicit integration diverges "
                           "(Study/timestep safety factors may exceed 1 to map that "
                           "limit)"));
    s.ratio_tolerance     = prm.get_double("equilibrium ratio");
    s.ramp_crossing_times = prm.get_double("ramp crossing times");
    s.phase_step_limit    = prm.get_integer("step limit");
    s.phase_time_limit    = prm.get_double("phase time limit");
    AssertThrow(s.ratio_tolerance > 0,
                ExcMessage("Coupling/equilibrium ratio must be > 0"));
    prm.leave_subsection();
    prm.enter_subsection("Output");
    s.vtk_interval        = prm.get_integer("interval");
    s.checkpoint_interval = prm.get_integer("checkpoint interval");
    prm.leave_subsection();
    // validated per run, after the sweep settings are applied
    return s;
  }
} // namespace demfem::apps
