// Material genesis (fistPkg §4.2): packing phase (§4.2.1, Table 7) and
// finalization phase (§4.2.2) with the flat-jointed microstructure of §2.6.2.
#include "dem/specimen/genesis.h"
#include "dem/specimen/memory_budget.h"
#include "dem/specimen/property_rules.h"

#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/specimen/servo.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>

namespace demfem::dem
{
  namespace
  {
    /// Number-mean grain volume of one size piece (diameter multiplier 1).
    template <int dim>
    double mean_grain_volume(const SizePiece &s)
    {
      double m2, m3; // E[d^2], E[d^3]
      if (s.gaussian)
        {
          m2 = s.mean * s.mean + s.sd * s.sd;
          m3 = s.mean * s.mean * s.mean + 3 * s.mean * s.sd * s.sd;
        }
      else
        {
          const double a = s.d_lo, b = s.d_hi;
          m2 = (a * a + a * b + b * b) / 3;
          m3 = (a + b) * (a * a + b * b) / 4;
        }
      return dim == 2 ? M_PI / 4 * m2 : M_PI / 6 * m3;
    }

    double draw_diameter(const SizePiece &s, Random &rng)
    {
      if (!s.gaussian)
        return rng.uniform(s.d_lo, s.d_hi);
      const double lo = s.d_hi > 0 ? s.d_lo : 0.0;
      const double hi = s.d_hi > 0 ? s.d_hi : s.mean + 4 * s.sd;
      for (int i = 0; i < 10000; ++i)
        {
          const double d = s.mean + s.sd * rng.normal();
          if (d > lo && d <= hi)
            return d;
        }
      return s.mean;
    }

    /// Mean pressure on the vessel walls (compression positive), Eq. 21.
    template <int dim>
    double wall_pressure(const Specimen<dim> &s)
    {
      double P = 0;
      for (int a = 0; a < dim; ++a)
        P -= s.vessel.wall_stress(s.model.walls, a);
      return P / dim;
    }

    template <int dim>
    double region_pressure(const Specimen<dim> &s)
    {
      double P = 0;
      for (const auto &r : s.vessel.regions)
        P -= mean_stress<dim>(region_stress(s.model, r));
      return P / 3;
    }

    /// Grain pairs with gap <= g (sort and sweep along x; O(N log N + pairs)).
    template <int dim>
    std::vector<std::pair<std::uint32_t, std::uint32_t>> close_pairs(
        const Particles<dim> &P, double g)
    {
      const std::size_t          N = P.size();
      std::vector<std::uint32_t> o(N);
      for (std::size_t i = 0; i < N; ++i)
        o[i] = static_cast<std::uint32_t>(i);
      std::sort(o.begin(), o.end(), [&](auto a, auto b) {
        return P.x[a][0] - P.radius[a] < P.x[b][0] - P.radius[b] ||
               (P.x[a][0] - P.radius[a] == P.x[b][0] - P.radius[b] && a < b);
      });
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
      for (std::size_t a = 0; a < N; ++a)
        {
          const std::uint32_t i    = o[a];
          const double        xmax = P.x[i][0] + P.radius[i] + g;
          for (std::size_t b = a + 1; b < N; ++b)
            {
              const std::uint32_t j = o[b];
              if (P.x[j][0] - P.radius[j] > xmax)
                break;
              const double gap = (P.x[j] - P.x[i]).norm() - P.radius[i] - P.radius[j];
              if (gap <= g)
                pairs.emplace_back(std::min(i, j), std::max(i, j));
            }
        }
      std::sort(pairs.begin(), pairs.end());
      return pairs;
    }

    template <int dim>
    void calm(Particles<dim> &P)
    {
      for (std::size_t i = 0; i < P.size(); ++i)
        {
          P.v[i].setZero();
          P.w[i].setZero();
        }
    }

    template <int dim>
    double max_overlap_ratio(const Model<dim> &m)
    {
      double r = 0;
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (!grp.is_wall[k] && grp.gap[k] < 0)
              {
                const double d = 2 * std::min(m.particles.radius[grp.end1[k]],
                                              m.particles.radius[grp.end2[k]]);
                r              = std::max(r, -grp.gap[k] / d);
              }
        }
      return r;
    }

    template <int dim>
    std::size_t n_active(const Model<dim> &m)
    {
      std::size_t n = 0;
      for (int g = 0; g < m.n_groups(); ++g)
        for (std::size_t k = 0; k < m.group(g).size(); ++k)
          n += m.group(g).active(k) ? 1 : 0;
      return n;
    }

    /// Moves every contact of group `from` (ball-ball only, or all) to `to`.
    template <int dim>
    void move_contacts(Model<dim> &m, int from, int to, bool walls_too)
    {
      auto                                                       &g = m.group(from);
      std::vector<std::tuple<std::uint32_t, std::uint32_t, bool>> c;
      for (std::size_t k = 0; k < g.size(); ++k)
        if (walls_too || !g.is_wall[k])
          c.emplace_back(g.end1[k], g.end2[k], g.is_wall[k]);
      for (auto &[i, j, w] : c)
        w ? m.install_wall(i, j, to) : m.install(i, j, to);
    }

    template <int dim>
    struct Packer
    {
      Specimen<dim>        &s;
      const MaterialParams &p;
      std::ostream         *out;
      std::int64_t          steps = 0;

      void step()
      {
        // The automatic time step is refreshed at contact detection and
        // counts active contacts only; contacts that close between passes
        // (walls moving in, grains growing) would leave it stale.
        if (steps % 50 == 0)
          {
            s.model.invalidate_contacts();
            // A non-finite force is a packing that blew up (a modulus so
            // large that the forces overflow), not a slow one: stop now,
            // not at the step limit. (The ratio is 0 while no force acts.)
            if (!std::isfinite(wall_pressure(s)) ||
                !std::isfinite(s.model.unbalanced_ratio()))
              throw PackingDiverged("material genesis: the packing diverged (non-finite "
                                    "forces) at step " +
                                    std::to_string(steps) +
                                    ": the contact moduli are out of any physical range");
          }
        s.model.step();
        if (++steps > p.step_limit)
          {
            std::ostringstream m;
            m << "material genesis: packing did not reach the material pressure " << p.Pm
              << " Pa within tolerance " << p.P_tol << " and ratio-average "
              << p.ratio_limit << " in step_limit = " << p.step_limit
              << " steps (pressure now " << wall_pressure(s) << " Pa, ratio "
              << s.model.unbalanced_ratio() << "); raise step_limit or P_tol";
            throw std::runtime_error(m.str());
          }
      }
      void report(const char *phase)
      {
        if (out)
          *out << "genesis: phase " << phase << ", step " << steps << ", grains "
               << s.model.particles.size() << ", wall pressure " << wall_pressure(s)
               << " Pa (";
        for (int a = 0; a < dim; ++a)
          if (out)
            *out << (a ? " " : "") << -s.vessel.wall_stress(s.model.walls, a);
        if (out)
          *out << "), ratio " << s.model.unbalanced_ratio() << "\n";
      }
      /// ft_eq: cycles until the ratio-average falls below the limit
      /// (at least `min_steps`; checked every 50 steps). Returns false when
      /// `max_steps` passed first.
      bool equilibrate(std::int64_t max_steps, std::int64_t min_steps = 50)
      {
        for (std::int64_t n = 1; n <= max_steps; ++n)
          {
            step();
            if (n >= min_steps && n % 50 == 0 && n_active(s.model) > 0 &&
                s.model.unbalanced_ratio() < p.ratio_limit)
              return true;
          }
        return false;
      }
    };

    // Radii scaling for grain scaling: r -> (1 + alpha) r, masses follow.
    template <int dim>
    void scale_radii(Model<dim> &m, double alpha, double density)
    {
      auto &P = m.particles;
      for (std::size_t i = 0; i < P.size(); ++i)
        {
          P.radius[i] *= 1 + alpha;
          P.mass[i]    = density * ball_volume<dim>(P.radius[i]);
          P.inertia[i] = (dim == 2 ? 0.5 : 0.4) * P.mass[i] * P.radius[i] * P.radius[i];
        }
      m.invalidate_contacts();
      m.reset_energy_baseline();
    }

    /// d P / d alpha for a uniform radius scaling: each active contact's
    /// overlap grows by alpha L (L = branch length), so the mean stress grows
    /// by alpha / (dim V) sum k_n l^2 (linear contacts).
    template <int dim>
    double pressure_modulus(const Model<dim> &m, double V)
    {
      double K = 0;
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (grp.active(k))
              {
                const Vec<dim> x1 = m.particles.x[grp.end1[k]];
                const Vec<dim> x2 =
                    grp.is_wall[k] ? grp.xc[k] : m.particles.x[grp.end2[k]];
                const double l = (x2 - x1).norm();
                K += grp.stiffness(k, m.particles).kn * l * l;
              }
        }
      return K / (dim * V);
    }
  } // namespace

  template <int dim>
  double mean_grain_volume(const MaterialParams &p)
  {
    // Grains per unit solid volume: sum over pieces of fraction / mean volume.
    double per_volume = 0;
    for (const auto &s : p.sizes)
      per_volume += s.volume_fraction /
                    (mean_grain_volume<dim>(s) * std::pow(p.diameter_multiplier, dim));
    return 1 / per_volume;
  }

  template <int dim>
  std::vector<double> draw_radii(const MaterialParams &p, double solid_volume,
                                 Random &rng)
  {
    std::vector<double> radii;
    for (const auto &piece : p.sizes)
      {
        double acc = 0;
        while (acc < piece.volume_fraction * solid_volume)
          {
            const double r = 0.5 * p.diameter_multiplier * draw_diameter(piece, rng);
            radii.push_back(r);
            acc += ball_volume<dim>(r);
          }
      }
    return radii;
  }

  template <int dim>
  double expected_grain_count(const MaterialParams &p, const VesselParams &v)
  {
    double Vv = v.H * v.W;
    if (dim == 3)
      Vv *= v.shape == "cylinder" ? M_PI * v.W / 4 : v.D;
    const double Vg = (1 - p.cloud_porosity_or_default(dim)) * Vv;
    double       n  = 0;
    for (const auto &s : p.sizes)
      n += s.volume_fraction * Vg /
           (mean_grain_volume<dim>(s) * std::pow(p.diameter_multiplier, dim));
    return n;
  }

  template <int dim>
  void set_grain_count(MaterialParams &p, const VesselParams &v, double n)
  {
    check_range("set_grain_count", "n", n, 1, HUGE_VAL);
    p.diameter_multiplier = 1;
    p.diameter_multiplier = std::pow(expected_grain_count<dim>(p, v) / n, 1.0 / dim);
  }

  template <int dim>
  Specimen<dim> build_specimen(const MaterialParams &p, const VesselParams &v,
                               std::ostream *progress, const std::string &where)
  {
    Random        rng(p.seed);
    Specimen<dim> s = pack_specimen<dim>(p, v, rng, progress, where);
    finalize_specimen(s, rng, progress);
    return s;
  }

  template <int dim>
  Specimen<dim> pack_specimen(const MaterialParams &p, const VesselParams &v, Random &rng,
                              std::ostream *progress, const std::string &where)
  {
    p.validate(where, dim);
    VesselParams vp = v;
    if (vp.emod == 0)
      vp.emod = p.lnm_emod;
    vp.validate(where, dim);

    Specimen<dim> s;
    s.material = p;
    s.vessel   = make_vessel(s.model.walls, vp, where);
    auto &m    = s.model;
    auto &P    = m.particles;

    // 1. Grain cloud of porosity n_c (overlaps not accounted for).
    const double Vv = s.vessel.volume(m.walls);
    const double Vg = (1 - p.cloud_porosity_or_default(dim)) * Vv;
    check_memory(Vg / mean_grain_volume<dim>(p), dim, p.memory_limit, where,
                 "Material/diameter multiplier (or lower Material/number of grains)",
                 "Problem/memory limit");
    const std::vector<double> radii   = draw_radii<dim>(p, Vg, rng);
    double                    Vgrains = 0;
    for (double r : radii)
      Vgrains += ball_volume<dim>(r);
    const double rho = p.bulk_density ? p.density * Vv / Vgrains : p.density;
    for (double r : radii)
      {
        Vec<dim> x;
        for (int tries = 0;; ++tries)
          {
            for (int a = 0; a < dim; ++a)
              {
                const double L = s.vessel.length(m.walls, a);
                if (2 * r >= L)
                  throw InputError(where + ": grain diameter " + std::to_string(2 * r) +
                                   " does not fit the vessel (length " +
                                   std::to_string(L) +
                                   "); check 'sizes' and the vessel size");
                x[a] = rng.uniform(-L / 2 + r, L / 2 - r);
              }
            if (s.vessel.contains(m.walls, x, r))
              break;
          }
        P.add(x, r, rho);
      }

    // Laws: packing group (linear, zero friction), grain-wall group, both
    // with the deformability method per contact (dem/specimen/property_rules.h).
    const int pack = m.template add_law<LinearLaw<dim>>(
        {}, where + " (packing linear group)",
        linear_rule<dim>({p.lnm_emod, p.lnm_krat}, 0.0));
    // Frictionless walls without shear stiffness (§4.1): kappa* = 0.
    s.wall_group = m.template add_law<LinearLaw<dim>>(
        {}, where + " (grain-wall group)", linear_rule<dim>({vp.emod, 0.0}, 0.0));
    m.set_default_law(pack, s.wall_group);
    m.local_damping = p.local_damping;
    m.set_timestep(0);

    Packer<dim> pk{s, p, progress};
    // 2. Zero-friction relaxation; calm every 5 steps until the largest
    // overlap ratio is below 0.25 (fistPkg footnote 34).
    for (int n = 1;; ++n)
      {
        pk.step();
        if (n % 5 == 0)
          {
            calm(P);
            if (max_overlap_ratio(m) < 0.25)
              break;
          }
      }
    // Grains whose centres escaped the vessel are deleted (footnote 34).
    {
      std::vector<char> out(P.size(), 0);
      bool              any = false;
      for (std::size_t i = 0; i < P.size(); ++i)
        any |= (out[i] = !s.vessel.contains(m.walls, P.x[i]));
      if (any)
        {
          if (progress)
            *progress << "genesis: removing " << std::count(out.begin(), out.end(), 1)
                      << " grains that escaped the vessel\n";
          m.remove_particles(out);
        }
    }
    m.reset_energy_baseline();
    while (!pk.equilibrate(1000) && wall_pressure(s) > 1e-3 * p.Pm)
      ;
    calm(P); // a loose cloud may still hold free-flying grains
    pk.report("relaxed");

    // 3. Material pressure.
    if (p.packing == "grain-scaling")
      {
        for (int it = 0;; ++it)
          {
            const double Pw = wall_pressure(s);
            if (std::abs(Pw - p.Pm) <= p.P_tol * p.Pm && n_active(m) > 0 &&
                m.unbalanced_ratio() < p.ratio_limit)
              break;
            const double K     = pressure_modulus(m, Vv);
            double       alpha = K > 0 ? (p.Pm - Pw) / K : 0.01;
            alpha              = std::clamp(alpha, -0.1, 0.05);
            scale_radii(m, alpha, rho);
            // A shrink can leave the assembly off the walls: then a cluster
            // rattles between them without contact damping and the ratio
            // never falls. Equilibrate in bounded chunks, stop loose grains
            // when the walls carry nothing, and let the next scaling grow
            // them back (the step limit still bounds the whole packing).
            if (!pk.equilibrate(std::min<std::int64_t>(p.step_limit, 20000)) &&
                wall_pressure(s) < p.P_tol * p.Pm)
              calm(P);
            if (it % 5 == 0)
              pk.report("grain scaling");
          }
      }
    else
      {
        const int conf = m.template add_law<LinearLaw<dim>>(
            {}, where + " (confinement linear group)",
            linear_rule<dim>({p.lnm_emod, p.lnm_krat}, p.fric_CA));
        move_contacts(m, pack, conf, false);
        m.set_default_law(conf, s.wall_group);
        // Walls first brought to the relaxed cloud (no travel through empty
        // space), then servo-controlled.
        for (int a = 0; a < dim; ++a)
          {
            const auto &V = s.vessel;
            if (V.lo[a] < 0 && !(a == 0 && V.cylinder()))
              continue;
            double gap = HUGE_VAL;
            for (std::size_t i = 0; i < P.size(); ++i)
              {
                if (V.lo[a] >= 0)
                  gap = std::min(
                      {gap,
                       P.x[i][a] - P.radius[i] - (V.center[a] - V.length(m.walls, a) / 2),
                       V.center[a] + V.length(m.walls, a) / 2 - P.x[i][a] - P.radius[i]});
                else
                  gap = std::min(gap, V.radius(m.walls) - P.radius[i] -
                                          std::hypot(P.x[i][0] - V.center[0],
                                                     P.x[i][1] - V.center[1]));
              }
            if (gap > 0)
              V.translate_outward(m.walls, a, -gap);
          }
        m.invalidate_contacts();
        m.reset_energy_baseline();
        ServoParams sp;
        sp.tol       = p.P_tol;
        sp.isotropic = true;
        // Automatic velocity limit: a wall hitting a grain at v loads it with
        // v sqrt(k m); keep that below 10 x the grain's share of Pm.
        // Grain-wall stiffness of a grain of the mean drawn radius.
        double rbar = 0;
        for (double r : radii)
          rbar += r;
        rbar /= radii.size();
        ContactGeometry<dim> gbw;
        gbw.R1               = rbar;
        gbw.ball_wall        = true;
        const double wall_kn = Deformability{vp.emod, 0.0}.kn_force(gbw);
        const double Ag      = dim == 2 ? 2 * rbar : M_PI * rbar * rbar;
        sp.v_limit =
            p.v_limit > 0
                ? p.v_limit
                : 10 * p.Pm * Ag / std::sqrt(wall_kn * rho * ball_volume<dim>(rbar));
        Servo<dim> servo(s.vessel, sp);
        for (int a = 0; a < dim; ++a)
          servo.set_pressure(a, p.Pm);
        for (std::int64_t n = 1;; ++n)
          {
            servo.update(m);
            pk.step();
            // The mean wall pressure is the criterion: per-axis control can
            // stall with a deviator the assembly carries at yield (measured
            // +-10 % in frictionless 2D boxes), which the walls cannot remove.
            if (n % 50 == 0 && std::abs(wall_pressure(s) - p.Pm) <= p.P_tol * p.Pm &&
                n_active(m) > 0 && m.unbalanced_ratio() < p.ratio_limit)
              break;
            if (n % 5000 == 0)
              pk.report("boundary contraction");
          }
        servo.stop(m);
      }
    pk.report("packed");
    s.packing_pressure        = wall_pressure(s);
    s.packing_region_pressure = region_pressure(s);
    s.packing_max_force       = max_contact_force(m);
    s.packing_ratio           = m.unbalanced_ratio();
    s.packing_steps           = pk.steps;
    if (p.bulk_density) // grain density from the final grain volume (Table 1)
      {
        double V = 0;
        for (double r : P.radius)
          V += ball_volume<dim>(r);
        scale_radii(m, 0.0, p.density * s.vessel.volume(m.walls) / V);
      }
    return s;
  }

  template Specimen<2> build_specimen(const MaterialParams &, const VesselParams &,
                                      std::ostream *, const std::string &);
  template Specimen<3> build_specimen(const MaterialParams &, const VesselParams &,
                                      std::ostream *, const std::string &);
  template Specimen<2> pack_specimen(const MaterialParams &, const VesselParams &,
                                     Random &, std::ostream *, const std::string &);
  template Specimen<3> pack_specimen(const MaterialParams &, const VesselParams &,
                                     Random &, std::ostream *, const std::string &);
  template double      mean_grain_volume<2>(const MaterialParams &);
  template double      mean_grain_volume<3>(const MaterialParams &);
  template std::vector<double> draw_radii<2>(const MaterialParams &, double, Random &);
  template std::vector<double> draw_radii<3>(const MaterialParams &, double, Random &);
  template double expected_grain_count<2>(const MaterialParams &, const VesselParams &);
  template double expected_grain_count<3>(const MaterialParams &, const VesselParams &);
  template void   set_grain_count<2>(MaterialParams &, const VesselParams &, double);
  template void   set_grain_count<3>(MaterialParams &, const VesselParams &, double);
} // namespace demfem::dem
