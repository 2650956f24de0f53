// `demfem calibrate FILE.prm`: material genesis (fistPkg §4) + laboratory tests
// (§5.4-5.7) -> material.json with the measured properties (E, nu for the
// continuum, docs/architecture.md, "Plane-stress and plane-strain constants").
// Every input is validated before the output directory is created, so a bad
// input writes nothing.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include "apps/calibrate.h"
#include "apps/calibrate_fit.h"
#include "apps/calibrate_voronoi.h"
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/parallel_packings.h"
#include "apps/prm_cli.h"
#include "dem/specimen/lab_tests.h"
#include "dem/specimen/memory_budget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace demfem::apps
{
  namespace
  {
    using namespace dealii;
    namespace fs = std::filesystem;

    const char *usage =
        "usage: demfem calibrate FILE.prm [--fit | --front FIT.csv] [--set "
        "\"Section/key=value\"]... "
        "[--overwrite] [--defaults] [--print-parameters] [--help]\n"
        "\n"
        "Builds a bonded-particle material (fistPkg §4: packing, finalization), runs\n"
        "the laboratory tests listed in Tests/tests (ucs, triaxial, uniaxial strain,\n"
        "brazilian, direct tension; each on a fresh specimen of the same seed) and\n"
        "writes to Problem/output directory: material.json (microparameters and\n"
        "measured properties with units; E, nu are the continuum's pair: 3D, or 2D\n"
        "plane strain), summary.json, history_<test>.csv, <test>_stress_strain.svg,\n"
        "VTK of the specimen and of each test at peak and at the end (.pvd).\n"
        "Exit 3 (summary.json status step_limit_reached) when a test ended at\n"
        "Tests/step limit before its post-peak end, (status brazilian_not_split)\n"
        "when the Brazilian disk did not split along its loaded diameter, or\n"
        "(status confinement_not_held) when a confined test's P_c deviated by more\n"
        "than Tests/confining tolerance before its peak.\n"
        "Material/type = rigid-voronoi | flexible-voronoi (2D): Voronoi grains\n"
        "(subsection Material/Voronoi, docs/voronoi.md) in the same tests (no uniaxial\n"
        "strain; brazilian rigid only), with VTK of cells, contact points, cracks.\n"
        "\n"
        "--fit  automatic calibration: searches the microparameters of Fit/parameters\n"
        "       for the targets of Fit/Targets (E, nu, ucs, bts, direct tension, crack\n"
        "       initiation ratio, mi) with an NLopt optimizer, Fit/seeds packings per\n"
        "       evaluation, elastic stage first; writes fit.csv (every evaluation),\n"
        "       fit.json, fit_convergence.svg, then calibrates the best material.\n"
        "       Exit 3 (status targets_not_reached) when a target stays outside its\n"
        "       tolerance. Every fit also writes fit_front.{csv,json,svg}: which\n"
        "       targets conflict (each met alone, never together) and each pair's\n"
        "       Pareto front; fit_levers.csv: what each parameter alone did to\n"
        "       each target in the fit's one-at-a-time steps.\n"
        "--front FIT.csv  no test: the same analysis of an earlier fit's log against\n"
        "       this file's Fit/Targets, into Problem/output directory.\n";

    // Test names of Tests/tests and what they run.
    const std::vector<TestSpec> known_tests = {
        {"ucs", dem::TestKind::compression, dem::CompressionType::unconfined},
        {"triaxial", dem::TestKind::compression, dem::CompressionType::confined},
        {"triaxial series", dem::TestKind::compression, dem::CompressionType::confined},
        {"uniaxial strain", dem::TestKind::compression,
         dem::CompressionType::uniaxial_strain},
        {"brazilian", dem::TestKind::brazilian, dem::CompressionType::unconfined},
        {"direct tension", dem::TestKind::direct_tension,
         dem::CompressionType::unconfined}};

    void dist(ParameterHandler &prm, const std::string &name, const std::string &mean,
              const std::string &doc)
    {
      prm.declare_entry(name + " mean", mean, Patterns::Double(), doc + " mean (>= 0)");
      prm.declare_entry(name + " sd", "0", Patterns::Double(),
                        doc + " standard deviation (>= 0)");
      prm.declare_entry(name + " min", "0", Patterns::Double(),
                        doc + " truncation point: draws at or below it are redrawn "
                              "(0: the normal truncated at zero; 0 <= min < mean)");
    }

    void declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Problem");
      prm.declare_entry("dimension", "2", Patterns::Integer(2, 3),
                        "2 (disks) or 3 (spheres)");
      prm.declare_entry("output directory", "out/calibrate", Patterns::Anything(),
                        "Created after validation; files in it are replaced");
      prm.declare_entry(
          "memory limit", "auto", Patterns::Anything(),
          "Refuse a specimen whose estimated memory exceeds this [GB]; auto: "
          "half the machine's memory");
      prm.declare_entry("vtk", "true", Patterns::Bool(),
                        "Write VTK of specimen and tests");
      prm.declare_entry(
          "seeds", "1", Patterns::Integer(1, 100),
          "Packings the tests run on (Material/seed, seed + 1, ...; 1 .. 100). "
          "Above 1 each packing's results go to seed_<n>/ and material.json "
          "holds the seed means, seed_scatter their standard deviations and "
          "seed_values the single values (a material is its seed mean, not "
          "one packing). The packings run side by side, one per OpenMP thread "
          "(OMP_NUM_THREADS), with the results of one at a time. With --fit: the "
          "packings of the best material's material.json (Fit/seeds those of each "
          "evaluation)");
      prm.leave_subsection();

      prm.enter_subsection("Material");
      prm.declare_entry(
          "type", "flatjointed",
          Patterns::Selection(
              std::string("linear|contactbonded|parallelbonded|flatjointed|") +
              voronoi_type_names()),
          "Material type (fistPkg Tables 2-5); rigid-voronoi, flexible-voronoi: "
          "Voronoi grains (2D, subsection Voronoi, docs/voronoi.md)");
      prm.declare_entry(
          "size distribution", "uniform 1.6e-3 2.4e-3 1", Patterns::Anything(),
          "Grain diameters [m] (fistPkg Table 1), pieces separated by ';': "
          "'uniform D_lo D_hi fraction' or 'gaussian mean sd D_lo D_hi fraction' "
          "(D_hi = 0: no upper cut); volume fractions sum to 1");
      prm.declare_entry("diameter multiplier", "1", Patterns::Double(), "D_mult (> 0)");
      prm.declare_entry(
          "number of grains", "0", Patterns::Double(),
          "> 0: sets the diameter multiplier so about this many grains fill "
          "the vessel; 0: use the diameter multiplier");
      prm.declare_entry("density", "2650", Patterns::Double(),
                        "Grain density [kg/m^3] (> 0)");
      prm.declare_entry("bulk density", "false", Patterns::Bool(),
                        "density is the bulk density");
      prm.declare_entry("local damping", "0.7", Patterns::Double(), "[0, 1)");
      prm.declare_entry("seed", "10000", Patterns::Integer(0), "Random seed (packing)");
      prm.declare_entry("linear effective modulus", "0", Patterns::Double(),
                        "lnm_emod E* [Pa] of the linear group (new contacts, packing)");
      prm.declare_entry("linear stiffness ratio", "1.5", Patterns::Double(), "lnm_krat");
      prm.declare_entry("linear friction", "0.4", Patterns::Double(), "lnm_fric");
      prm.declare_entry("effective modulus", "0", Patterns::Double(),
                        "E* [Pa] of the bonded contacts");
      prm.declare_entry("stiffness ratio", "1.5", Patterns::Double(), "kappa*");
      prm.declare_entry("friction", "0.4", Patterns::Double(), "mu of the bonded group");
      prm.declare_entry("installation gap", "0", Patterns::Double(), "g_i [m] (>= 0)");
      prm.enter_subsection("Contact bond");
      dist(prm, "tensile strength", "0", "Tensile strength [Pa]");
      dist(prm, "shear strength", "0", "Shear strength [Pa]");
      prm.leave_subsection();
      prm.enter_subsection("Parallel bond");
      prm.declare_entry("radius multiplier", "1", Patterns::Double(), "pb_rmul");
      prm.declare_entry("bond effective modulus", "0", Patterns::Double(),
                        "pb_bemod [Pa]");
      prm.declare_entry("bond stiffness ratio", "1", Patterns::Double(), "pb_bkrat");
      prm.declare_entry("moment contribution factor", "0", Patterns::Double(), "pb_mcf");
      dist(prm, "tensile strength", "0", "Tensile strength [Pa]");
      dist(prm, "cohesion", "0", "Cohesion [Pa]");
      prm.declare_entry("friction angle", "0", Patterns::Double(), "[deg]");
      prm.leave_subsection();
      prm.enter_subsection("Flat joint");
      prm.declare_entry("bonded fraction", "1", Patterns::Double(), "phi_B");
      prm.declare_entry("gapped fraction", "0", Patterns::Double(),
                        "phi_G (slit fraction = 1 - phi_B - phi_G)");
      dist(prm, "gap", "0", "Initial surface gap of gapped joints [m]");
      prm.declare_entry("radial elements", "2", Patterns::Integer(1),
                        "N_r (2D: elements)");
      prm.declare_entry("circumferential elements", "4", Patterns::Integer(3),
                        "N_alpha (3D)");
      prm.declare_entry("radius multiplier code", "0", Patterns::Integer(0, 2),
                        "0 fixed, 1 valid non-uniform, 2 valid uniform (fistPkg §2.6.2)");
      prm.declare_entry("radius multiplier", "1", Patterns::Double(), "lambda");
      dist(prm, "tensile strength", "0", "Tensile strength [Pa]");
      dist(prm, "cohesion", "0", "Cohesion [Pa]");
      prm.declare_entry("friction angle", "0", Patterns::Double(), "[deg]");
      prm.leave_subsection();
      declare_voronoi_parameters(prm);
      prm.leave_subsection();

      prm.enter_subsection("Vessel");
      prm.declare_entry("shape", "box", Patterns::Selection("box|cylinder"),
                        "cylinder: 3D only");
      prm.declare_entry("height", "0.1", Patterns::Double(), "H (axial) [m]");
      prm.declare_entry("width", "0.05", Patterns::Double(),
                        "W (x; cylinder diameter) [m]");
      prm.declare_entry("depth", "0.05", Patterns::Double(), "D (y, 3D box) [m]");
      prm.declare_entry("expansion factor", "1.2", Patterns::Double(), ">= 1");
      prm.declare_entry("wall effective modulus", "0", Patterns::Double(),
                        "E* of grain-wall contacts [Pa]; 0: linear effective modulus");
      prm.leave_subsection();

      prm.enter_subsection("Packing");
      prm.declare_entry("method", "grain-scaling",
                        Patterns::Selection("grain-scaling|boundary-contraction"),
                        "fistPkg §4.2.1");
      prm.declare_entry("material pressure", "1e6", Patterns::Double(),
                        "P_m [Pa] (compression positive)");
      prm.declare_entry("pressure tolerance", "0.01", Patterns::Double(), "eps_P");
      prm.declare_entry("ratio limit", "8e-3", Patterns::Double(), "ft_eq ratio limit");
      prm.declare_entry("step limit", "2000000", Patterns::Integer(1),
                        "ft_eq step limit");
      prm.declare_entry("cloud porosity", "-1", Patterns::Double(),
                        "n_c; < 0: Table 7 default");
      prm.leave_subsection();

      prm.enter_subsection("Joint");
      prm.declare_entry("enabled", "false", Patterns::Bool(),
                        "insert a smooth-jointed interface (fistPkg §2.8) after genesis");
      prm.declare_entry(
          "point", "0, 0, 0", Patterns::List(Patterns::Double(), 2, 3),
          "a point of the joint plane [m] (x, y[, z]), relative to the vessel centre");
      prm.declare_entry("dip", "0", Patterns::Double(0, 360),
                        "dip angle [deg] (seed 001 Eq. 1)");
      prm.declare_entry("dip direction", "0", Patterns::Double(0, 180),
                        "dip direction [deg] (3D)");
      prm.declare_entry("normal stiffness", "1e13", Patterns::Double(0), "sj_kn [Pa/m]");
      prm.declare_entry("shear stiffness", "1e13", Patterns::Double(0), "sj_ks [Pa/m]");
      prm.declare_entry("friction", "0.5", Patterns::Double(0), "sj_fric");
      prm.declare_entry("dilation angle", "0", Patterns::Double(0, 89.999),
                        "sj_da [deg]");
      prm.declare_entry("bonded", "false", Patterns::Bool(), "bond the joint (S_j = 3)");
      prm.declare_entry("tensile strength", "0", Patterns::Double(0), "sj_ten [Pa]");
      prm.declare_entry("cohesion", "0", Patterns::Double(0), "sj_coh [Pa]");
      prm.declare_entry("friction angle", "0", Patterns::Double(0, 89.999),
                        "sj_fa [deg]");
      prm.declare_entry("radius multiplier", "1", Patterns::Double(0), "sj_rmul");
      prm.leave_subsection();

      prm.enter_subsection("Tests");
      prm.declare_entry(
          "tests", "ucs, brazilian, direct tension",
          Patterns::List(
              Patterns::Selection(
                  "ucs|triaxial|triaxial series|uniaxial strain|brazilian|direct "
                  "tension"),
              1),
          "Tests to run, each on a fresh specimen");
      prm.declare_entry("strain rate", "0.1", Patterns::Double(),
                        "Axial strain rate [1/s] (> 0)");
      prm.declare_entry("confining pressure", "10e6", Patterns::Double(),
                        "P_c [Pa] of the triaxial / uniaxial-strain tests (>= 0)");
      prm.declare_entry(
          "confining pressures", "0, 5e6, 10e6, 20e6, 40e6",
          Patterns::List(Patterns::Double(), 2),
          "P_c [Pa] of each test of the triaxial series (>= 0, at least two distinct; "
          "0 runs an unconfined test); Mohr-Coulomb and Hoek-Brown are fitted to the "
          "peaks");
      prm.declare_entry(
          "load fraction", "0.7", Patterns::Double(),
          "Test ends when the load falls below this fraction of its peak (0, 1)");
      prm.declare_entry("strain limit", "0.02", Patterns::Double(),
                        "|axial strain| limit (0, 1]");
      prm.declare_entry("step limit", "400000", Patterns::Integer(1),
                        "Loading steps limit");
      prm.declare_entry("history interval", "50", Patterns::Integer(1),
                        "Steps per history row");
      prm.declare_entry("grip thickness", "0.1", Patterns::Double(),
                        "t_g / H (direct tension)");
      prm.declare_entry(
          "servo velocity limit", "0", Patterns::Double(),
          "Largest speed [m/s] of the confining servo's walls in loading (>= 0; "
          "in seating it only lowers the automatic limit); 0: automatic, 10 x "
          "strain rate x height (fistPkg Table 10), in seating at most P_c / "
          "(rho c), in loading at least 2 P_c / (rho c) (docs/calibrate.md)");
      prm.declare_entry(
          "lateral wall segments", "1", Patterns::Integer(1),
          "Confined compression, 2D: the lateral walls as flexible chains of this "
          "many facets between the platens, each vertex servo-controlled to P_c on "
          "its own (a membrane); 1: rigid walls. Each facet at least two mean grain "
          "diameters long (docs/calibrate.md, \"Confining servo\")");
      prm.declare_entry(
          "confining boundary", "walls", Patterns::Selection("walls|pressure"),
          "Confined compression: walls (servo-controlled, rigid or flexible: "
          "lateral wall segments) or, 2D, pressure: from the seating on, P_c as "
          "forces on the outermost grains instead of lateral walls, a triaxial "
          "cell's membrane (docs/calibrate.md, \"Confining boundary\")");
      prm.declare_entry(
          "confining tolerance", "0.01", Patterns::Double(),
          "Confined compression: largest deviation of the confining pressure from "
          "P_c up to the peak (averaged over a compression wave's crossing time), "
          "as a fraction of P_c, for the test to count as held at P_c; beyond it "
          "the run ends with status confinement_not_held, exit 3 (0 < tolerance "
          "<= 1)");
      prm.declare_entry(
          "platen friction", "0.5", Patterns::Double(),
          "Brazilian platen friction (fistPkg: frictionless; a small 2D disk "
          "between frictionless platens can slide out sideways) (>= 0)");
      prm.declare_entry(
          "brazilian diameter", "0", Patterns::Double(),
          "Diameter [m] of a Brazilian specimen packed on its own at the material's "
          "grain size (a box of that size, 3D: brazilian thickness deep); 0: the disk "
          "is carved from the vessel (diameter min(width, height)). A 3D disk needs "
          "about 20 grains across to split (>= 0)");
      prm.declare_entry(
          "brazilian flat angle", "0", Patterns::Double(),
          "Flattened Brazilian disk: angle 2 alpha [deg] each loaded flat subtends "
          "at the centre (the flats load a band 2 R sin alpha wide; strength "
          "k F / (pi R t), k = sin 2 alpha / alpha - 1: 0.960 at 20 deg); 0: the "
          "round disk of fistPkg (0 .. 20)");
      prm.declare_entry("brazilian thickness", "0", Patterns::Double(),
                        "3D Brazilian specimen of its own: thickness [m]; 0: half the "
                        "brazilian diameter (ISRM t/D = 0.5) (>= 0)");
      prm.declare_entry("fit window low", "0.1", Patterns::Double(),
                        "E/nu fit from this fraction");
      prm.declare_entry("fit window high", "0.5", Patterns::Double(),
                        "... to this fraction of peak");
      prm.declare_entry(
          "crack initiation method", "volumetric strain",
          Patterns::Selection(dem::crack_initiation_method_names),
          "What material.json's crack_initiation is (all three are reported): the "
          "onset of dilatancy in the crack volumetric strain (Martin & Chandler "
          "1994), the onset of steady cracking in the crack count, or the lateral "
          "strain response (Nicksiar & Martin 2012: farthest from the line to crack "
          "damage)");
      prm.declare_entry(
          "crack initiation fraction", "0.01", Patterns::Double(),
          "Crack count method: crack initiation when cracks reach this fraction of "
          "those at peak (0, 1)");
      prm.declare_entry(
          "crack volumetric strain fraction", "0.05", Patterns::Double(),
          "Volumetric method: the crack volumetric strain has left zero "
          "when it stays above this fraction of the elastic volumetric strain at the "
          "peak (0, 1)");
      prm.declare_entry(
          "brazilian split fraction", "0.5", Patterns::Double(),
          "Brazilian failure mode: the disk split along the loaded diameter when at "
          "least this fraction of its failure's cracks (those after the peak, at "
          "least a split's worth) lie in the central strip of width D/3 without the "
          "D/6 next to each platen; else its BTS is no tensile strength: a warning, "
          "status brazilian_not_split, exit 3, and --fit leaves that packing out of "
          "the BTS mean (0, 1]");
      prm.declare_entry("seating ratio limit", "1e-4", Patterns::Double(),
                        "ft_eq ratio of seating");
      prm.declare_entry("seating step limit", "20000", Patterns::Integer(0), "");
      prm.declare_entry(
          "time step safety", "0.8", Patterns::Double(),
          "Time step of the tests as a fraction of the critical one (0, 1]; a "
          "quasi-static test does not depend on it");
      prm.declare_entry(
          "loading rate check", "false", Patterns::Selection("false|true|half|quarter"),
          "Repeat each test on the same packing at half (true, half) or at half and "
          "quarter (quarter) the strain rate; a peak moving more than 2 % flags the "
          "test as not quasi-static (fistPkg §5.4)");
      prm.leave_subsection();

      prm.enter_subsection("Fit");
      prm.declare_entry(
          "parameters", "", Patterns::Anything(),
          "Microparameters searched by --fit, 'name lo hi' separated by ';', e.g. "
          "'effective modulus 20e9 120e9; tensile strength mean 2e6 40e6' (names: see "
          "docs/calibrate.md)");
      prm.declare_entry(
          "seeds", "3", Patterns::Anything(),
          "Packings (seeds seed, seed+1, ...) averaged per evaluation (>= 1), run "
          "side by side, one per OpenMP thread");
      prm.declare_entry(
          "brazilian seeds", "0", Patterns::Anything(),
          "Brazilian disks (seeds seed, seed+1, ...) the bts target is averaged over "
          "per evaluation, 0-100 (0: Fit/seeds); those beyond Fit/seeds run the "
          "Brazilian test only");
      prm.declare_entry("evaluations", "60", Patterns::Anything(),
                        "Evaluation budget of each stage (>= 1)");
      prm.declare_entry("algorithm", "bobyqa",
                        Patterns::Selection("bobyqa|subplex|nelder-mead|cobyla"),
                        "NLopt derivative-free optimizer");
      prm.declare_entry(
          "elastic strain", "3e-4", Patterns::Anything(),
          "Axial strain of the elastic stage's small-strain test (0, 0.01]");
      prm.declare_entry(
          "resume from", "", Patterns::Anything(),
          "fit.csv of an earlier --fit run of the same parameters and targets (e.g. "
          "one stopped by the end of a session): its evaluations are replayed in "
          "order without measuring, and the search goes on from where it stopped; "
          "read before the output directory is claimed, so it may lie in it");
      prm.enter_subsection("Targets");
      for (const char *t :
           {"E", "nu", "ucs", "bts", "direct tension", "crack initiation ratio", "mi"})
        prm.declare_entry(t, "", Patterns::Anything(),
                          "'value[, weight[, relative tolerance]]' (defaults 1, 0.05); "
                          "empty: not a target");
      prm.leave_subsection();
      prm.leave_subsection();
    }

    using Settings = CalibrateSettings;

    // Physical checks that patterns cannot express name the key, the file
    // and the allowed range (docs/architecture.md, "Input validation").
    void check(const std::string &where, const std::string &key, double v, double lo,
               double hi, bool lo_open = false, bool hi_open = false)
    {
      dem::check_range(where, key, v, lo, hi, lo_open, hi_open);
    }

    dem::Distribution read_dist(ParameterHandler &prm, const std::string &where,
                                const std::string &section, const std::string &name)
    {
      dem::Distribution d{prm.get_double(name + " mean"), prm.get_double(name + " sd"),
                          prm.get_double(name + " min")};
      check(where, section + name + " mean", d.mean, 0, HUGE_VAL);
      check(where, section + name + " sd", d.sd, 0, HUGE_VAL);
      if (d.min != 0) // below the mean, so that the redrawing ends
        check(where, section + name + " min", d.min, 0, d.mean, false, true);
      return d;
    }

    std::vector<dem::SizePiece> parse_sizes(const std::string &text,
                                            const std::string &where)
    {
      const std::string           key = "Material/size distribution";
      std::vector<dem::SizePiece> pieces;
      std::stringstream           all(text);
      double                      sum = 0;
      for (std::string item; std::getline(all, item, ';');)
        {
          std::stringstream s(item);
          std::string       kind;
          s >> kind;
          if (kind.empty())
            continue;
          dem::SizePiece      p;
          std::vector<double> v;
          for (double x; s >> x;)
            v.push_back(x);
          const bool bad_tail = !s.eof();
          if (kind == "uniform" && v.size() == 3 && !bad_tail)
            p.d_lo = v[0], p.d_hi = v[1], p.volume_fraction = v[2];
          else if (kind == "gaussian" && v.size() == 5 && !bad_tail)
            {
              p.gaussian = true;
              p.mean = v[0], p.sd = v[1], p.d_lo = v[2], p.d_hi = v[3],
              p.volume_fraction = v[4];
            }
          else
            throw dem::InputError(
                where + ": " + key + ": cannot read piece '" + item +
                "' (allowed: 'uniform D_lo D_hi fraction' or 'gaussian mean sd D_lo D_hi "
                "fraction', pieces separated by ';')");
          if (p.gaussian)
            {
              check(where, key + " (gaussian mean)", p.mean, 0, HUGE_VAL, true);
              check(where, key + " (gaussian sd)", p.sd, 0, HUGE_VAL);
              check(where, key + " (D_lo)", p.d_lo, 0, HUGE_VAL);
              if (p.d_hi != 0)
                check(where, key + " (D_hi)", p.d_hi, p.d_lo, HUGE_VAL, true);
            }
          else
            {
              check(where, key + " (D_lo)", p.d_lo, 0, HUGE_VAL, true);
              check(where, key + " (D_hi)", p.d_hi, p.d_lo, HUGE_VAL);
            }
          check(where, key + " (volume fraction)", p.volume_fraction, 0, 1, true);
          sum += p.volume_fraction;
          pieces.push_back(p);
        }
      if (pieces.empty())
        throw dem::InputError(where + ": " + key + ": no size piece given");
      if (std::abs(sum - 1) > 1e-9)
        {
          std::ostringstream m;
          m << where << ": " << key << ": volume fractions sum to " << sum
            << "; they must sum to 1";
          throw dem::InputError(m.str());
        }
      return pieces;
    }

    Settings read_settings(ParameterHandler &prm, const std::string &where, bool fit)
    {
      Settings s;
      s.where       = where;
      s.fit.enabled = fit;
      prm.enter_subsection("Problem");
      s.dim   = prm.get_integer("dimension");
      s.out   = prm.get("output directory");
      s.vtk   = prm.get_bool("vtk");
      s.seeds = prm.get_integer("seeds");
      if (const auto ml = prm.get("memory limit"); ml != "auto")
        s.mat.memory_limit =
            1e9 * parse_number(where + ": Problem/memory limit", ml, 1e-6,
                               std::numeric_limits<double>::max(), "GB");
      prm.leave_subsection();
      if (s.out.empty())
        throw dem::InputError(where + ": Problem/output directory must not be empty");

      auto &m = s.mat;
      prm.enter_subsection("Material");
      m.type                = prm.get("type");
      m.sizes               = parse_sizes(prm.get("size distribution"), where);
      m.diameter_multiplier = prm.get_double("diameter multiplier");
      check(where, "Material/diameter multiplier", m.diameter_multiplier, 0, HUGE_VAL,
            true);
      s.n_grains = prm.get_double("number of grains");
      check(where, "Material/number of grains", s.n_grains, 0, 1e8);
      m.density = prm.get_double("density");
      check(where, "Material/density", m.density, 0, HUGE_VAL, true);
      m.bulk_density  = prm.get_bool("bulk density");
      m.local_damping = prm.get_double("local damping");
      check(where, "Material/local damping", m.local_damping, 0, 1, false, true);
      m.seed     = prm.get_integer("seed");
      m.lnm_emod = prm.get_double("linear effective modulus");
      m.lnm_krat = prm.get_double("linear stiffness ratio");
      m.lnm_fric = prm.get_double("linear friction");
      m.emod     = prm.get_double("effective modulus");
      m.krat     = prm.get_double("stiffness ratio");
      m.fric     = prm.get_double("friction");
      m.igap     = prm.get_double("installation gap");
      check(where, "Material/linear effective modulus", m.lnm_emod, 0, HUGE_VAL, true);
      check(where, "Material/linear stiffness ratio", m.lnm_krat, 0, HUGE_VAL, true);
      check(where, "Material/linear friction", m.lnm_fric, 0, HUGE_VAL);
      if (m.is_bonded())
        {
          check(where, "Material/effective modulus", m.emod, 0, HUGE_VAL, true);
          check(where, "Material/stiffness ratio", m.krat, 0, HUGE_VAL, true);
        }
      check(where, "Material/friction", m.fric, 0, HUGE_VAL);
      check(where, "Material/installation gap", m.igap, 0, HUGE_VAL);
      prm.enter_subsection("Contact bond");
      m.cb_tens   = read_dist(prm, where, "Material/Contact bond/", "tensile strength");
      m.cb_shears = read_dist(prm, where, "Material/Contact bond/", "shear strength");
      prm.leave_subsection();
      prm.enter_subsection("Parallel bond");
      const std::string pb = "Material/Parallel bond/";
      m.pb_rmul            = prm.get_double("radius multiplier");
      m.pb_bemod           = prm.get_double("bond effective modulus");
      m.pb_bkrat           = prm.get_double("bond stiffness ratio");
      m.pb_mcf             = prm.get_double("moment contribution factor");
      m.pb_ten             = read_dist(prm, where, pb, "tensile strength");
      m.pb_coh             = read_dist(prm, where, pb, "cohesion");
      m.pb_fa              = prm.get_double("friction angle");
      check(where, pb + "radius multiplier", m.pb_rmul, 0, HUGE_VAL, true);
      check(where, pb + "moment contribution factor", m.pb_mcf, 0, 1);
      check(where, pb + "friction angle", m.pb_fa, 0, 90, false, true);
      prm.leave_subsection();
      prm.enter_subsection("Flat joint");
      const std::string fj = "Material/Flat joint/";
      m.fj_B               = prm.get_double("bonded fraction");
      m.fj_G               = prm.get_double("gapped fraction");
      m.fj_gap             = read_dist(prm, where, fj, "gap");
      m.fj_Nr              = prm.get_integer("radial elements");
      m.fj_Nal             = prm.get_integer("circumferential elements");
      m.fj_rmul_code       = prm.get_integer("radius multiplier code");
      m.fj_rmul            = prm.get_double("radius multiplier");
      m.fj_ten             = read_dist(prm, where, fj, "tensile strength");
      m.fj_coh             = read_dist(prm, where, fj, "cohesion");
      m.fj_fa              = prm.get_double("friction angle");
      check(where, fj + "bonded fraction", m.fj_B, 0, 1);
      // B + G <= 1 (the rest slit) up to the round-off MaterialParams
      // allows, so that bonded 0.9 with gapped 0.1 is accepted; the counts
      // are clamped to the joints there are (dem/specimen/property_rules.cc).
      check(where, fj + "gapped fraction", m.fj_G, 0,
            1 - m.fj_B + dem::fraction_sum_tolerance);
      check(where, fj + "radius multiplier", m.fj_rmul, 0, 1, true);
      check(where, fj + "friction angle", m.fj_fa, 0, 90, false, true);
      prm.leave_subsection();
      prm.leave_subsection();

      auto &v = s.vessel;
      prm.enter_subsection("Vessel");
      v.shape  = prm.get("shape");
      v.H      = prm.get_double("height");
      v.W      = prm.get_double("width");
      v.D      = s.dim == 3 ? prm.get_double("depth") : 1.0;
      v.expand = prm.get_double("expansion factor");
      v.emod   = prm.get_double("wall effective modulus");
      check(where, "Vessel/height", v.H, 0, HUGE_VAL, true);
      check(where, "Vessel/width", v.W, 0, HUGE_VAL, true);
      check(where, "Vessel/depth", v.D, 0, HUGE_VAL, true);
      check(where, "Vessel/expansion factor", v.expand, 1, HUGE_VAL);
      check(where, "Vessel/wall effective modulus", v.emod, 0, HUGE_VAL);
      if (s.dim == 2 && v.shape == "cylinder")
        throw dem::InputError(where +
                              ": Vessel/shape: 'cylinder' needs Problem/dimension = 3 "
                              "(allowed in 2D: box)");
      prm.leave_subsection();

      prm.enter_subsection("Packing");
      m.packing        = prm.get("method");
      m.Pm             = prm.get_double("material pressure");
      m.P_tol          = prm.get_double("pressure tolerance");
      m.ratio_limit    = prm.get_double("ratio limit");
      m.step_limit     = prm.get_integer("step limit");
      m.cloud_porosity = prm.get_double("cloud porosity");
      check(where, "Packing/material pressure", m.Pm, 0, HUGE_VAL);
      check(where, "Packing/pressure tolerance", m.P_tol, 0, 1, true);
      check(where, "Packing/ratio limit", m.ratio_limit, 0, 1, true);
      if (m.cloud_porosity >= 0)
        check(where, "Packing/cloud porosity", m.cloud_porosity, 0, 1, true, true);
      prm.leave_subsection();

      prm.enter_subsection("Joint");
      s.joint = prm.get_bool("enabled");
      {
        const auto pt = Utilities::split_string_list(prm.get("point"));
        for (std::size_t a = 0; a < pt.size() && a < 3; ++a)
          s.joint_point[a] = Utilities::string_to_double(pt[a]);
      }
      auto &sj   = s.joint_sj;
      sj.dip     = prm.get_double("dip");
      sj.ddir    = prm.get_double("dip direction");
      sj.sj_kn   = prm.get_double("normal stiffness");
      sj.sj_ks   = prm.get_double("shear stiffness");
      sj.sj_fric = prm.get_double("friction");
      sj.sj_da   = prm.get_double("dilation angle");
      sj.bonded  = prm.get_bool("bonded");
      sj.sj_ten  = prm.get_double("tensile strength");
      sj.sj_coh  = prm.get_double("cohesion");
      sj.sj_fa   = prm.get_double("friction angle");
      sj.sj_rmul = prm.get_double("radius multiplier");
      if (s.joint)
        sj.validate(where + ", subsection Joint");
      prm.leave_subsection();

      auto &l = s.lab;
      prm.enter_subsection("Tests");
      for (const auto &name : Utilities::split_string_list(prm.get("tests")))
        for (const auto &t : known_tests)
          if (t.name == name)
            s.tests.push_back(t);
      l.strain_rate               = prm.get_double("strain rate");
      l.Pc                        = prm.get_double("confining pressure");
      l.load_fraction             = prm.get_double("load fraction");
      l.strain_limit              = prm.get_double("strain limit");
      l.step_limit                = prm.get_integer("step limit");
      l.history_interval          = prm.get_integer("history interval");
      l.grip_thickness            = prm.get_double("grip thickness");
      l.platen_friction           = prm.get_double("platen friction");
      l.servo.v_limit             = prm.get_double("servo velocity limit");
      l.lateral_segments          = prm.get_integer("lateral wall segments");
      l.pressure_boundary         = prm.get("confining boundary") == "pressure";
      l.fit_lo                    = prm.get_double("fit window low");
      l.fit_hi                    = prm.get_double("fit window high");
      l.crack_initiation_fraction = prm.get_double("crack initiation fraction");
      l.crack_initiation_method =
          dem::parse_crack_initiation_method(prm.get("crack initiation method"));
      l.crack_volumetric_fraction = prm.get_double("crack volumetric strain fraction");
      l.split_fraction            = prm.get_double("brazilian split fraction");
      l.confining_tolerance       = prm.get_double("confining tolerance");
      l.brazilian_diameter        = prm.get_double("brazilian diameter");
      l.brazilian_thickness       = prm.get_double("brazilian thickness");
      l.brazilian_flat_angle      = prm.get_double("brazilian flat angle");
      l.ratio_limit               = prm.get_double("seating ratio limit");
      l.seat_step_limit           = prm.get_integer("seating step limit");
      l.timestep_safety           = prm.get_double("time step safety");
      const std::string rate      = prm.get("loading rate check");
      s.rate_check                = rate == "quarter" ? 2 : (rate == "false" ? 0 : 1);
      for (const auto &p : Utilities::split_string_list(prm.get("confining pressures")))
        s.confining_pressures.push_back(Utilities::string_to_double(p));
      const std::string t = "Tests/";
      for (double Pc : s.confining_pressures)
        check(where, t + "confining pressures", Pc, 0, HUGE_VAL);
      if (std::count_if(s.confining_pressures.begin(), s.confining_pressures.end(),
                        [&](double Pc) { return Pc != s.confining_pressures[0]; }) == 0)
        throw std::invalid_argument(where +
                                    ": Tests/confining pressures: the series needs "
                                    "at least two distinct pressures");
      // The key's 0 is no "keep the specimen's step" (the library's 0).
      check(where, t + "time step safety", l.timestep_safety, 0, 1, true);
      l.validate(where, s.dim, t);
      prm.leave_subsection();

      prm.enter_subsection("Fit");
      read_fit_settings(prm, where, s.fit, [&](const FitParameter &p) {
        dem::MaterialParams probe = s.mat;
        fit_parameter(probe, p.name, where); // a known name for this material type
        const bool fraction = p.name == "bonded fraction" || p.name == "gapped fraction";
        if (fraction && p.hi > 1)
          throw std::invalid_argument(where + ": Fit/parameters (" + p.name +
                                      "): a fraction lies in [0, 1]");
      });
      prm.leave_subsection();

      // The library's own checks (same ranges; any remaining combination).
      m.validate(where, s.dim);
      v.validate(where, s.dim);
      // The specimen's memory, estimated before the output directory is
      // made (genesis checks it again where the grains are drawn).
      const double n = s.n_grains > 0 ? s.n_grains
                       : s.dim == 2   ? dem::expected_grain_count<2>(m, v)
                                      : dem::expected_grain_count<3>(m, v);
      // Packings side by side (apps/parallel_packings.h) are in memory
      // together: one specimen each, so the budget is for all of them.
      const int side_by_side = packings_at_a_time(
          fit ? std::max({s.fit.seeds, s.fit.brazilian_disks(), s.seeds}) : s.seeds);
      const std::string fewer_grains =
          "Material/diameter multiplier (or lower Material/number of grains";
      dem::check_memory(n * side_by_side, s.dim, m.memory_limit,
                        side_by_side > 1 ? where + " (" + std::to_string(side_by_side) +
                                               " packings side by side, one per OpenMP "
                                               "thread)"
                                         : where,
                        fewer_grains + (side_by_side > 1 ? ", or OMP_NUM_THREADS)" : ")"),
                        "Problem/memory limit");
      return s;
    }
  } // namespace

  int run_calibrate(int argc, char **argv)
  {
    try
      {
        // --fit is this command's own flag: taken out before the common
        // command line is read.
        std::vector<char *> args;
        bool                fit = false;
        std::string         front; // --front FIT.csv: an earlier fit's log
        for (int i = 0; i < argc; ++i)
          if (std::string(argv[i]) == "--fit")
            fit = true;
          else if (std::string(argv[i]) == "--front")
            {
              if (i + 1 >= argc)
                throw std::invalid_argument("--front: give the fit.csv of a --fit run");
              front = argv[++i];
            }
          else
            args.push_back(argv[i]);
        if (fit && !front.empty())
          throw std::invalid_argument("--front analyses an earlier fit's log: not with "
                                      "--fit (a fit writes fit_front.* itself)");
        std::string      file;
        ParameterHandler prm;
        declare_parameters(prm);
        if (answered(read_parameters(int(args.size()), args.data(), prm, usage, file),
                     prm, usage, &std::cout))
          return 0;
        prm.enter_subsection("Material");
        const bool voronoi = is_voronoi_type(prm.get("type"));
        prm.leave_subsection();
        if (voronoi)
          {
            // Voronoi grains: their own keys and runner; the specimens are
            // built before the output directory, so a material that fails
            // at install (a fracture energy below a contact's brittle
            // value) writes nothing.
            const VoronoiCalibrateSettings v = read_voronoi_settings(prm, file, fit);
            if (!front.empty())
              return run_fit_front(prm, file, v.fit, v.out, front);
            if (v.fit.enabled)
              {
                RunDirectory           run(v.out, prm);
                const CalibrateOutcome outcome = run_voronoi_fit(v);
                run.finish(outcome.status, outcome.exit_code);
                return outcome.exit_code;
              }
            const VoronoiSpecimens specimens = make_voronoi_specimens(v);
            RunDirectory           run(v.out, prm);
            const CalibrateOutcome outcome = run_voronoi_calibration(v, specimens);
            run.finish(outcome.status, outcome.exit_code);
            return outcome.exit_code;
          }
        const Settings s = read_settings(prm, file, fit);
        if (!front.empty())
          return run_fit_front(prm, file, s.fit, s.out, front);
        // The run owns its output directory: lock, manifest.json, and an
        // earlier run's results refused unless --overwrite.
        RunDirectory           run(s.out, prm);
        const CalibrateOutcome outcome =
            s.fit.enabled ? (s.dim == 2 ? run_fit<2>(s) : run_fit<3>(s))
                          : (s.dim == 2 ? run_calibration_seeds<2>(s)
                                        : run_calibration_seeds<3>(s));
        run.finish(outcome.status, outcome.exit_code);
        return outcome.exit_code;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem calibrate: error: " << exception_text(e) << std::endl;
        return 1;
      }
  }
} // namespace demfem::apps
