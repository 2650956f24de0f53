// `demfem bench dem`: speed of the DEM engine on a dense, fully flat-jointed
// assembly under constant-strain compression. Only the stepping
// is timed; the scene set-up (generation, detection, installation) is not.
//
// Scene. Grains sit on a jittered lattice of spacing a = 2 r0 (2D hexagonal,
// 3D face-centred cubic) with radii uniform in [0.8, 1.2] r0, so lattice
// neighbours overlap or leave a gap of at most 0.4 r0. Every ball-ball pair
// with a gap below 0.1 r0 receives a bonded flat joint (memo Table 5; g_o = 0
// so the interface is installed stress-free whatever the geometric overlap,
// memo Eq. 31), kn/ks from the deformability method (memo Eq. 40, E* = 50 GPa,
// kappa* = 2) per contact (kn = E*/L, L = R1 + R2), infinite strengths so the
// run stays elastic. The bottom layer is held fixed and the
// top layer moves down at a constant velocity (axial strain rate 0.1 /s, i.e.
// a strain of order 1e-5 over a benchmark run). Pairs that come within the
// skin later get a linear contact (the usual default law).
#include "apps/commands.h"
#include "dem/engine/model.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/material_file.h"
#include "dem/specimen/property_rules.h"
#include "dem/voronoi/voronoi_lab_test.h"

#include <nlohmann/json.hpp>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace
{
  using namespace demfem::dem;

  struct BenchOptions
  {
    int          dim     = 2;
    std::int64_t n       = 10000;
    std::int64_t steps   = 1000;
    int          threads = 1;
    bool         json    = false;
    bool         dim_set = false;
    std::string  material; ///< material.json: the scene is that material
    /// `demfem bench voronoi`: the rigid Voronoi model (seed 004) against
    /// the 2D flat-joint scene of the same N, steps and threads.
    bool voronoi = false;
  };

  struct BenchResult
  {
    std::size_t n_particles = 0, n_contacts = 0, n_flatjoints = 0;
    double setup_s = 0, wall_s = 0, cpu_s = 0, timestep = 0, unbalanced = 0, kinetic = 0;
    int    elements = 0;
    std::string material; ///< "" for the single-group scene
    std::size_t n_bonded = 0, n_gapped = 0, n_slit = 0;
  };

  constexpr double r0      = 1e-3; // mean grain radius [m]
  constexpr double density = 2650; // [kg/m^3]
  constexpr double emod    = 50e9; // E* [Pa]
  constexpr double kratio  = 2.0;  // kappa*
  constexpr double rate    = 0.1;  // axial strain rate [1/s]
  constexpr double max_gap = 0.1;  // installation gap / r0

  void print_usage(std::ostream &out)
  {
    out << "usage: demfem bench [dem] --dim 2|3 --n N --steps S --threads T [--json]\n"
           "       demfem bench [dem] --material FILE --n N --steps S --threads T "
           "[--json]\n"
           "       demfem bench voronoi --n N --steps S --threads T [--json]\n"
           "\n"
           "Times S steps of a dense, fully flat-jointed assembly of N grains under\n"
           "constant-strain compression (2D Nr = 2; 3D Nr = 2, Nal = 8). Only the\n"
           "stepping is timed.\n"
           "  --material FILE  material.json of demfem calibrate (flat-jointed): the\n"
           "                 scene takes its size distribution, stiffnesses, strength\n"
           "                 distributions, bonded/gapped/slit fractions, radius-\n"
           "                 multiplier code and Nr/Nal, and its dimension\n"
           "  --dim 2|3      model dimension (default 2; with --material: the file's)\n"
           "  --n N          number of grains, 8 <= N <= 100000000 (default 10000)\n"
           "  --steps S      number of timed steps, 1 <= S <= 1e9 (default 1000)\n"
           "  --threads T    OpenMP threads, 1 <= T <= 1024 (default 1)\n"
           "  --json         print one JSON object instead of the text report\n"
           "\n"
           "demfem bench voronoi: cost per grain-step of rigid and flexible Voronoi "
           "grains (seed\n"
           "004: Laguerre cells of a jittered hexagonal packing, three contact points\n"
           "per shared edge, bilinear softening) against the 2D flat-joint scene\n"
           "above with the same N, steps and threads (docs/voronoi.md).\n";
  }

  /// Parses an integer option value in [lo, hi]; throws a message naming it.
  std::int64_t parse_int(const std::string &opt, const char *value, std::int64_t lo,
                         std::int64_t hi, const std::string &allowed)
  {
    if (value == nullptr)
      throw std::invalid_argument("option " + opt + " needs a value (" + allowed + ")");
    char *end         = nullptr;
    errno             = 0;
    const long long v = std::strtoll(value, &end, 10);
    if (end == value || *end != '\0' || errno != 0 || v < lo || v > hi)
      throw std::invalid_argument("invalid value '" + std::string(value) +
                                  "' for option " + opt + " (allowed: " + allowed + ")");
    return v;
  }

  BenchOptions parse(int argc, char **argv, bool &help)
  {
    BenchOptions o;
    int          a = 1;
    if (a < argc && std::strcmp(argv[a], "dem") == 0)
      ++a;
    else if (a < argc && std::strcmp(argv[a], "voronoi") == 0)
      o.voronoi = true, ++a;
    for (; a < argc; ++a)
      {
        const std::string opt   = argv[a];
        const char       *value = a + 1 < argc ? argv[a + 1] : nullptr;
        if (opt == "--help" || opt == "-h")
          help = true;
        else if (opt == "--json")
          o.json = true;
        else if (opt == "--dim")
          o.dim     = static_cast<int>(parse_int(opt, value, 2, 3, "2 or 3")),
          o.dim_set = true, ++a;
        else if (opt == "--material")
          {
            if (value == nullptr)
              throw std::invalid_argument(
                  "option --material needs a value (a material.json "
                  "written by demfem calibrate)");
            o.material = value;
            ++a;
          }
        else if (opt == "--n")
          o.n = parse_int(opt, value, 8, 100000000, "an integer 8 <= N <= 100000000"),
          ++a;
        else if (opt == "--steps")
          o.steps =
              parse_int(opt, value, 1, 1000000000, "an integer 1 <= S <= 1000000000"),
          ++a;
        else if (opt == "--threads")
          o.threads = static_cast<int>(
              parse_int(opt, value, 1, 1024, "an integer 1 <= T <= 1024")),
          ++a;
        else
          throw std::invalid_argument(
              "unknown option '" + opt +
              "' (allowed: dem, voronoi, --dim 2|3, --material FILE, --n N, "
              "--steps S, --threads T, --json, --help)");
      }
    if (o.voronoi && ((o.dim_set && o.dim != 2) || !o.material.empty()))
      throw std::invalid_argument("demfem bench voronoi is 2D and uses its own scenes "
                                  "(allowed: --n, --steps, --threads, --json)");
    return o;
  }

  /// CPU time of the whole process (all threads), user + system [s].
  double process_cpu_seconds()
  {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
           1e-6 * u.ru_stime.tv_usec;
  }

  // Portable uniform deviate (std distributions differ across libraries).
  double uniform(std::mt19937_64 &g, double a, double b)
  {
    return a + (b - a) * (static_cast<double>(g() >> 11) * 0x1.0p-53);
  }

  /// Lattice sites, layer by layer along the last axis (so truncating at N
  /// cuts the top layer), spacing a between nearest neighbours.
  template <int dim>
  std::vector<Vec<dim>> lattice(std::int64_t n, double a)
  {
    std::vector<Vec<dim>> x;
    x.reserve(n);
    if constexpr (dim == 2)
      {
        // Hexagonal: rows a*sqrt(3)/2 apart, odd rows shifted by a/2.
        const std::int64_t nx =
            std::max<std::int64_t>(2, std::llround(std::sqrt(double(n))));
        for (std::int64_t row = 0; static_cast<std::int64_t>(x.size()) < n; ++row)
          for (std::int64_t i = 0; i < nx && static_cast<std::int64_t>(x.size()) < n; ++i)
            x.emplace_back((i + 0.5 * (row % 2)) * a, row * a * std::sqrt(3.0) / 2);
      }
    else
      {
        // Face-centred cubic: cubic cell c = a sqrt(2) with 4 sites; nxy cells
        // across, whole cell layers split into their two atomic planes.
        const double       c = a * std::sqrt(2.0);
        const std::int64_t nxy =
            std::max<std::int64_t>(1, std::llround(std::cbrt(n / 4.0)));
        const double plane[2][2][2] = {{{0, 0}, {0.5, 0.5}}, {{0.5, 0}, {0, 0.5}}};
        for (std::int64_t layer = 0; static_cast<std::int64_t>(x.size()) < n; ++layer)
          {
            const int          half = layer % 2;
            const std::int64_t kz   = layer / 2;
            for (std::int64_t j = 0; j < nxy; ++j)
              for (std::int64_t i = 0; i < nxy; ++i)
                for (int s = 0; s < 2 && static_cast<std::int64_t>(x.size()) < n; ++s)
                  x.emplace_back((i + plane[half][s][0]) * c, (j + plane[half][s][1]) * c,
                                 (kz + 0.5 * half) * c);
          }
      }
    return x;
  }

  /// The material a scene is made of: the single-group default (uniform
  /// radii in [0.8, 1.2] r0, E* = 50 GPa, kappa* = 2, unbreakable, all
  /// bonded) or a material file's microparameters.
  struct SceneMaterial
  {
    std::string    file;
    int            dim = 2; ///< the file's, or --dim
    MaterialParams p;
  };

  SceneMaterial scene_material(const BenchOptions &o)
  {
    SceneMaterial s;
    s.dim = o.dim;
    if (o.material.empty())
      {
        s.p.type          = "flatjointed";
        s.p.sizes         = {SizePiece{false, 1.6 * r0, 2.4 * r0, 0, 0, 1.0}};
        s.p.density       = density;
        s.p.lnm_emod      = emod;
        s.p.lnm_krat      = kratio;
        s.p.lnm_fric      = 0.5;
        s.p.emod          = emod;
        s.p.krat          = kratio;
        s.p.fric          = 0.5;
        s.p.fj_Nr         = 2;
        s.p.fj_Nal        = 8;
        s.p.fj_ten        = {1e20, 0};
        s.p.fj_coh        = {1e20, 0};
        s.p.local_damping = 0.7;
        return s;
      }
    s.file               = o.material;
    const MaterialFile f = read_material_file(o.material);
    if (o.dim_set && o.dim != f.dim)
      throw InputError("--dim " + std::to_string(o.dim) +
                       " contradicts the material file '" + o.material + "' (dim " +
                       std::to_string(f.dim) + ")");
    if (f.material.type != "flatjointed")
      throw InputError("material file '" + o.material + "': type '" + f.material.type +
                       "': the benchmark scene is flat-jointed (allowed: flatjointed)");
    s.p   = f.material;
    s.dim = f.dim;
    return s;
  }

  template <int dim>
  BenchResult run_dem(const BenchOptions &o, const SceneMaterial &mat)
  {
    using clock    = std::chrono::steady_clock;
    const auto  t0 = clock::now();
    const auto &p  = mat.p;
    Model<dim>  model;
    model.local_damping = p.local_damping;

    // Radii: the single-group scene draws uniform radii in [0.8, 1.2] r0 with
    // its own generator (the figures in docs/bench.md); a material draws
    // from its size distribution (dem/specimen/genesis.h), shuffled so that the
    // pieces mix. Lattice spacing a = 2 x the mean radius.
    std::mt19937_64     gen(12345);
    std::vector<double> radii;
    if (!mat.file.empty())
      {
        Random rng(p.seed);
        radii = draw_radii<dim>(p, 1.05 * o.n * mean_grain_volume<dim>(p), rng);
        for (std::size_t k = radii.size(); k-- > 1;)
          std::swap(radii[k], radii[rng.index(k + 1)]);
        while (static_cast<std::int64_t>(radii.size()) < o.n)
          radii.push_back(radii[rng.index(radii.size())]);
        radii.resize(o.n);
      }
    double rbar = r0;
    if (!mat.file.empty())
      {
        rbar = 0;
        for (double r : radii)
          rbar += r / radii.size();
      }
    const double a = 2 * rbar;
    {
      std::size_t k = 0;
      for (const Vec<dim> &site : lattice<dim>(o.n, a))
        {
          // Jitter of up to 1e-3 r: breaks the symmetry of the contact
          // normals without changing which pairs are bonded.
          Vec<dim> x = site;
          for (int d = 0; d < dim; ++d)
            x[d] += uniform(gen, -1e-3, 1e-3) * rbar;
          const double r = mat.file.empty() ? uniform(gen, 0.8, 1.2) * r0 : radii[k];
          model.particles.add(x, r, p.density);
          ++k;
        }
    }
    auto &P = model.particles;

    // Platens: bottom layer fixed, top layer moving down (constant strain rate).
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const auto &x : P.x)
      lo = std::min(lo, x[dim - 1]), hi = std::max(hi, x[dim - 1]);
    const double height = hi - lo;
    const double layer  = 0.5 * a; // below any layer spacing (2D 0.87 a, 3D 0.71 a)
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        if (P.x[i][dim - 1] < lo + layer)
          P.fixity[i] = fix_all;
        else if (P.x[i][dim - 1] > hi - layer)
          {
            P.fixity[i]     = fix_all;
            P.v[i][dim - 1] = -rate * height;
          }
      }

    // Laws: linear contacts for pairs detected by the skin, then a bonded flat
    // joint on every pair with gap < 0.1 r (the material's installation gap
    // if larger); stiffnesses per contact by the deformability method (memo
    // Eq. 40, kn = E*/L), strengths drawn per contact (dem/specimen/property_rules.h).
    const auto fj    = flat_joint_params<dim>(p);
    const int  g_lin = model.template add_law<LinearLaw<dim>>(
        {}, "bench linear", linear_rule<dim>({p.lnm_emod, p.lnm_krat}, p.lnm_fric));
    const int g_fj = model.template add_law<FlatJointLaw<dim>>(
        fj, "bench flatjoint",
        flat_joint_rule<dim>({p.emod, p.krat}, p.fj_ten, p.fj_coh,
                             StrengthDraws(p.seed + 1)));
    model.set_default_law(g_lin, -1);
    const double bond_gap = std::max(max_gap * rbar, p.igap);
    model.skin            = bond_gap;
    model.detect_contacts();
    JointList joints;
    joints.group = g_fj;
    {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
      const auto                                          &G = model.group(g_lin);
      pairs.reserve(G.size());
      for (std::size_t k = 0; k < G.size(); ++k)
        if (G.gap[k] < bond_gap)
          pairs.emplace_back(G.end1[k], G.end2[k]);
      for (const auto &[i, j] : pairs)
        {
          const ContactRef c = model.install(i, j, g_fj);
          joints.index.push_back(c.index);
          joints.i.push_back(std::min(i, j));
          joints.j.push_back(std::max(i, j));
        }
    }
    BenchResult r;
    if (!mat.file.empty())
      {
        // The material's microstructure (fistPkg §2.6.2): valid radius
        // multipliers, then bonded / gapped / slit joints.
        set_radius_multipliers(model, joints, p.fj_rmul_code, p.fj_rmul);
        Random rng(p.seed + 2);
        designate_microstructure(model, joints, p.fj_B, p.fj_G, p.fj_gap, rng);
        const auto &G = model.group(g_fj);
        for (std::size_t k = 0; k < G.size(); ++k)
          {
            const int t = static_cast<int>(G.property(k, "fj_mtype"));
            (t == 1 ? r.n_bonded : t == 2 ? r.n_gapped : r.n_slit)++;
          }
      }
    model.skin = 0; // default 0.1 * min radius for the run
    model.set_timestep(0);
    model.detect_contacts(); // time step from the flat-joint stiffnesses

    r.material     = mat.file;
    r.n_particles  = P.size();
    r.n_contacts   = model.n_contacts();
    r.n_flatjoints = model.group(g_fj).size();
    r.elements     = FlatJointLaw<dim>::element_count(fj);
    r.timestep     = model.timestep();
    r.setup_s      = std::chrono::duration<double>(clock::now() - t0).count();

    const double c1 = process_cpu_seconds();
    const auto   t1 = clock::now();
    model.cycle(o.steps);
    r.wall_s     = std::chrono::duration<double>(clock::now() - t1).count();
    r.cpu_s      = process_cpu_seconds() - c1;
    r.unbalanced = model.unbalanced_ratio();
    r.kinetic    = model.kinetic_energy();
    return r;
  }

  void report(const BenchOptions &o, const BenchResult &r)
  {
    const double ps = double(r.n_particles) * o.steps / r.wall_s;
    const double cs = double(r.n_contacts) * o.steps / r.wall_s;
    if (o.json)
      {
        nlohmann::ordered_json j;
        j["benchmark"]    = "dem";
        j["law"]          = "flatjoint";
        j["material"]     = r.material.empty() ? "single-group scene" : r.material;
        j["dim"]          = o.dim;
        j["n_particles"]  = r.n_particles;
        j["n_contacts"]   = r.n_contacts;
        j["n_flatjoints"] = r.n_flatjoints;
        j["elements_per_contact"] = r.elements;
        if (!r.material.empty())
          {
            j["n_bonded"] = r.n_bonded;
            j["n_gapped"] = r.n_gapped;
            j["n_slit"]   = r.n_slit;
          }
        j["threads"]                         = o.threads;
        j["steps"]                           = o.steps;
        j["setup_s"]                         = r.setup_s;
        j["wall_s"]                          = r.wall_s;
        j["cpu_s"]                           = r.cpu_s;
        j["timestep"]                        = r.timestep;
        j["particle_steps_per_s"]            = ps;
        j["contact_updates_per_s"]           = cs;
        j["particle_steps_per_s_per_thread"] = ps / o.threads;
        j["unbalanced_ratio"]                = r.unbalanced;
        j["kinetic_energy"]                  = r.kinetic;
        std::cout << j.dump() << "\n";
        return;
      }
    char buf[2048];
    std::snprintf(
        buf, sizeof buf,
        "demfem bench dem: %dD flat-joint assembly under constant-strain compression\n"
        "  material             %s\n"
        "  particles            %zu\n"
        "  contacts             %zu (%zu flat joints, %d elements each)\n",
        o.dim, r.material.empty() ? "single-group scene" : r.material.c_str(),
        r.n_particles, r.n_contacts, r.n_flatjoints, r.elements);
    std::cout << buf;
    if (!r.material.empty())
      std::cout << "  microstructure       " << r.n_bonded << " bonded, " << r.n_gapped
                << " gapped, " << r.n_slit << " slit\n";
    std::snprintf(buf, sizeof buf,
                  "  threads              %d\n"
                  "  steps                %lld (time step %.4g s)\n"
                  "  setup                %.3f s (not timed)\n"
                  "  stepping wall time   %.3f s (CPU time %.3f s)\n"
                  "  particle steps / s   %.4g (%.4g per thread)\n"
                  "  contact updates / s  %.4g\n"
                  "  unbalanced ratio     %.3g at the end\n",
                  o.threads, static_cast<long long>(o.steps), r.timestep, r.setup_s,
                  r.wall_s, r.cpu_s, ps, ps / o.threads, cs, r.unbalanced);
    std::cout << buf;
  }

  /// The rigid and flexible Voronoi models' costs per grain-step next to
  /// the flat-joint scene's `fj` (same N, steps, threads), with their time
  /// steps (a flexible grain's elements bound its step).
  void report_voronoi(const BenchOptions &o, const BenchResult &fj)
  {
    namespace vor         = demfem::dem::voronoi;
    const double fj_cost  = fj.wall_s / (double(fj.n_particles) * o.steps);
    double       dt_rigid = 0, dt_flexible = 0;
    const double rigid = vor::voronoi_cost_per_grain_step(
        static_cast<int>(o.n), static_cast<int>(o.steps), 1, &dt_rigid);
    const double flexible = vor::flexible_voronoi_cost_per_grain_step(
        static_cast<int>(o.n), static_cast<int>(o.steps), 1, &dt_flexible);
    if (o.json)
      {
        nlohmann::ordered_json j;
        j["benchmark"]                            = "voronoi";
        j["n"]                                    = o.n;
        j["steps"]                                = o.steps;
        j["threads"]                              = o.threads;
        j["flatjoint_s_per_grain_step"]           = fj_cost;
        j["rigid_voronoi_s_per_grain_step"]       = rigid;
        j["rigid_voronoi_over_flatjoint_cost"]    = rigid / fj_cost;
        j["flexible_voronoi_s_per_grain_step"]    = flexible;
        j["flexible_voronoi_over_flatjoint_cost"] = flexible / fj_cost;
        j["rigid_voronoi_time_step_s"]            = dt_rigid;
        j["flexible_voronoi_time_step_s"]         = dt_flexible;
        std::cout << j.dump() << "\n";
        return;
      }
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "demfem bench voronoi: %lld grains, %lld steps, %d thread(s)\n"
                  "  flat joint (2D scene, Nr = 2)      %.3g us per grain-step\n"
                  "  rigid Voronoi (3 points/edge)      %.3g us per grain-step "
                  "(%.3g x flat joint), dt %.3g s\n"
                  "  flexible Voronoi (CST grains)      %.3g us per grain-step "
                  "(%.3g x flat joint), dt %.3g s\n",
                  static_cast<long long>(o.n), static_cast<long long>(o.steps), o.threads,
                  1e6 * fj_cost, 1e6 * rigid, rigid / fj_cost, dt_rigid, 1e6 * flexible,
                  flexible / fj_cost, dt_flexible);
    std::cout << buf;
  }
} // namespace

int demfem::apps::run_bench(int argc, char **argv)
{
  BenchOptions o;
  bool         help = false;
  try
    {
      o = parse(argc, argv, help);
    }
  catch (const std::invalid_argument &e)
    {
      std::cerr << "demfem bench: " << e.what() << "\n";
      print_usage(std::cerr);
      return 2;
    }
  if (help)
    {
      print_usage(std::cout);
      return 0;
    }
  omp_set_num_threads(o.threads);
  try
    {
      const SceneMaterial mat = scene_material(o);
      o.dim                   = mat.dim;
      const BenchResult r     = o.dim == 2 ? run_dem<2>(o, mat) : run_dem<3>(o, mat);
      if (o.voronoi)
        report_voronoi(o, r);
      else
        report(o, r);
    }
  catch (const std::exception &e)
    {
      std::cerr << "demfem bench: " << e.what() << "\n";
      return 1;
    }
  return 0;
}
