// `demfem contact-test`: the two-grain test of the flat-joint memo §2.1.
// Two grains just touching along +y, both with fully prescribed motion;
// the contact (flat joint or parallel bond, fully bonded, infinite strength)
// is driven through the DEM engine and its force and moment are printed as
// contact-plane components (memo Eq. 58, Fn > 0 tension).
#include "apps/cli.h"
#include "apps/commands.h"
#include "dem/engine/law_registry.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

namespace demfem::apps
{
  namespace
  {
    struct ContactTestOptions
    {
      std::string model = "flatjoint";
      int         dim   = 2;
      std::string load  = "axial";
      int         Nr    = -1; // -1: memo default (2D 4, 3D 2)
      int         Nal   = -1; // -1: memo default 8
      double      radius = 6.25e-3;
      double      rmul   = 0.8;
      double      E      = 29e9;
      double      nu     = 0.15;
      double      density = 2650;
      long        steps   = 1000;
    };

    const char *usage =
      "usage: demfem contact-test [options]\n"
      "Two-grain test of the flat-joint memo §2.1: two grains just touching,\n"
      "fully bonded contact of infinite strength, motion imposed quasi-statically.\n"
      "Prints one JSON object {\"Fn\",\"Fss\",\"Fst\",\"Mt\",\"Mbs\",\"Mbt\"} (N, N·m;\n"
      "contact-plane components, Fn > 0 tension).\n\n"
      "options:\n"
      "  --model flatjoint|parallelbond   contact model (default flatjoint)\n"
      "  --dim 2|3                        dimension (default 2)\n"
      "  --case axial|twist|bend          axial opening 1 mm, twist 0.2 rad (3D), bend 0.4 rad\n"
      "  --Nr N                           flat-joint elements, radial (default 4 in 2D, 2 in 3D)\n"
      "  --Nal N                          flat-joint elements, circumferential, 3D (default 8)\n"
      "  --radius R                       grain radius [m] (default 6.25e-3)\n"
      "  --rmul L                         radius multiplier (default 0.8)\n"
      "  --E E                            Young's modulus [Pa] (default 29e9)\n"
      "  --nu NU                          Poisson's ratio (default 0.15)\n"
      "  --steps N                        loading steps (default 1000)\n";

    ContactTestOptions parse(int argc, char **argv)
    {
      ContactTestOptions o;
      for (int a = 1; a < argc; ++a)
        {
          const std::string opt = argv[a];
          if (a + 1 >= argc)
            throw UsageError("option " + opt + " needs a value (see --help)");
          const std::string val = argv[++a];
          if (opt == "--model")
            {
              if (val != "flatjoint" && val != "parallelbond")
                throw UsageError("option --model: '" + val + "' is not one of flatjoint, parallelbond");
              o.model = val;
            }
          else if (opt == "--dim")
            o.dim = static_cast<int>(parse_int(opt, val, 2, 3));
          else if (opt == "--case")
            {
              if (val != "axial" && val != "twist" && val != "bend")
                throw UsageError("option --case: '" + val + "' is not one of axial, twist, bend");
              o.load = val;
            }
          else if (opt == "--Nr")
            o.Nr = static_cast<int>(parse_int(opt, val, 1, 1000));
          else if (opt == "--Nal")
            o.Nal = static_cast<int>(parse_int(opt, val, 3, 10000));
          else if (opt == "--radius")
            o.radius = parse_double(opt, val);
          else if (opt == "--rmul")
            o.rmul = parse_double(opt, val);
          else if (opt == "--E")
            o.E = parse_double(opt, val);
          else if (opt == "--nu")
            o.nu = parse_double(opt, val);
          else if (opt == "--steps")
            o.steps = parse_int(opt, val, 1, 100000000);
          else
            throw UsageError("unknown option '" + opt + "' (see --help)");
        }
      if (!(o.radius > 0))
        throw UsageError("option --radius: must be > 0");
      if (!(o.rmul > 0))
        throw UsageError("option --rmul: must be > 0");
      if (!(o.E > 0))
        throw UsageError("option --E: must be > 0");
      if (!(o.nu > -1 && o.nu < 0.5))
        throw UsageError("option --nu: must be in (-1, 0.5)");
      if (o.load == "twist" && o.dim == 2)
        throw UsageError("option --case twist: twisting exists only in 3D (use --dim 3)");
      if (o.Nal > 0 && o.dim == 2)
        throw UsageError("option --Nal: only meaningful with --dim 3");
      return o;
    }

    template <int dim>
    dem::ContactForce run(const ContactTestOptions &o)
    {
      using namespace dem;
      Model<dim> model;
      Vec<dim>   x2 = Vec<dim>::Zero();
      x2[1]         = 2 * o.radius; // just touching, contact normal +y
      model.particles.add(Vec<dim>::Zero(), o.radius, o.density);
      model.particles.add(x2, o.radius, o.density);
      for (auto &f : model.particles.fixity)
        f = fix_all; // motion fully prescribed on both grains
      model.local_damping = 0.7;

      // Beam-equivalent stiffnesses (memo Eq. 56/62): kn = E/L, ks = G/L.
      const double  L  = 2 * o.radius;
      const double  kn = o.E / L;
      const double  ks = o.E / (2 * (1 + o.nu) * L);
      LawProperties props;
      if (o.model == "flatjoint")
        props = {{"fj_Nr", o.Nr > 0 ? o.Nr : (dim == 2 ? 4 : 2)},
                 {"fj_Nal", o.Nal > 0 ? o.Nal : 8},
                 {"fj_rmul", o.rmul},
                 {"fj_kn", kn},
                 {"fj_ks", ks},
                 {"fj_ten", 1e20},
                 {"fj_coh", 1e20},
                 {"fj_bonded", 1}};
      else
        props = {{"pb_kn", kn},   {"pb_ks", ks},   {"pb_rmul", o.rmul}, {"pb_mcf", 1},
                 {"pb_ten", 1e20}, {"pb_coh", 1e20}, {"pb_bonded", 1}};
      const int  g = add_law_by_name(model, o.model, props, "contact-test options");
      const auto c = model.install(0, 1, g);

      // Quasi-static: the step is a fraction of the contact's own critical
      // step so the imposed motion is spread over many small increments.
      const ContactStiffness k = model.group(g).stiffness(c.index, model.particles);
      const double           dt = 0.1 * std::sqrt(model.particles.mass[1] / std::max(k.kn, k.ks));
      model.set_timestep(dt);
      const double T = dt * static_cast<double>(o.steps);

      const Vec<dim> n = model.group(g).n_prev[c.index];
      if (o.load == "axial")
        model.particles.v[1] = (1e-3 / T) * n; // opening of 1 mm
      else if constexpr (dim == 3)
        {
          const Vec<3> s = model.group(g).s_axis[c.index];
          const Vec<3> t = n.cross(s);
          // Relative twist +0.2 rad about n, relative bend +0.4 rad about t
          // (memo Eq. 60-61), split equally and oppositely between the two
          // grains so that the contact points do not slide (no shear).
          const Vec<3> w = o.load == "twist" ? Vec<3>((0.2 / T) * n) : Vec<3>((0.4 / T) * t);
          model.particles.w[1] = 0.5 * w;
          model.particles.w[0] = -0.5 * w;
        }
      else
        {
          // theta_bs = -theta_k = +0.4 rad, split between the grains as in 3D
          model.particles.w[1][0] = -0.2 / T;
          model.particles.w[0][0] = +0.2 / T;
        }
      model.cycle(o.steps);
      return model.group(g).local_force[c.index];
    }
  } // namespace

  int run_contact_test(int argc, char **argv)
  {
    for (int a = 1; a < argc; ++a)
      if (std::string(argv[a]) == "--help" || std::string(argv[a]) == "-h")
        {
          std::cout << usage;
          return 0;
        }
    try
      {
        const ContactTestOptions o = parse(argc, argv);
        const dem::ContactForce  f = o.dim == 2 ? run<2>(o) : run<3>(o);
        std::printf("{\"Fn\":%.10g,\"Fss\":%.10g,\"Fst\":%.10g,\"Mt\":%.10g,\"Mbs\":%.10g,\"Mbt\":%.10g}\n",
                    f.Fn + 0.0, f.Fss + 0.0, f.Fst + 0.0, f.Mt + 0.0, f.Mbs + 0.0, f.Mbt + 0.0);
        return 0;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem contact-test: error: " << e.what() << "\n";
        return 2;
      }
  }
} // namespace demfem::apps
