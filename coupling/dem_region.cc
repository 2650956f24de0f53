#include "coupling/dem_region.h"

#include "dem/measure/measurement.h"
#include "dem/specimen/memory_budget.h"
#include "dem/specimen/property_rules.h"

#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace demfem::coupling
{
  using dem::Vec;

  void RegionParams::validate(const std::string &w, int dim) const
  {
    const double inf = HUGE_VAL;
    dem::check_range(w, "DEM region/radius", radius, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (smallest)", d_lo, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (largest)", d_hi, d_lo, inf);
    dem::check_range(w, "DEM region/density", density, 0, inf, true);
    dem::check_range(w, "DEM region/porosity", porosity, 0.05, 0.5);
    dem::check_range(w, "DEM region/local damping", damping, 0, 1, false, true);
    dem::check_range(w, "DEM region/lnm emod", lnm_emod, 0, inf, true);
    dem::check_range(w, "DEM region/lnm krat", lnm_krat, 0, inf, true);
    dem::check_range(w, "DEM region/lnm fric", lnm_fric, 0, inf);
    dem::check_range(w, "DEM region/emod", emod, 0, inf, true);
    dem::check_range(w, "DEM region/krat", krat, 0, inf, true);
    dem::check_range(w, "DEM region/fric", fric, 0, inf);
    dem::check_range(w, "DEM region/igap", igap, 0, inf);
    dem::check_range(w, "DEM region/fj Nr", fj_Nr, 1, 64);
    dem::check_range(w, "DEM region/fj ten", fj_ten, 0, inf);
    dem::check_range(w, "DEM region/fj coh", fj_coh, 0, inf);
    dem::check_range(w, "DEM region/fj fa", fj_fa, 0, 90, false, true);
    if (d_hi > 0.25 * radius)
      throw dem::InputError(w + ": DEM region/grain diameter " + std::to_string(d_hi) +
                            " m is too large for the region radius " +
                            std::to_string(radius) + " m (allowed: <= radius/4)");
    // Grains of the packed region (2D: the disk r < b, per unit thickness;
    // 3D: the slab), estimated before anything is allocated.
    const double d  = mean_diameter();
    const double Vr = M_PI * radius * radius * (dim == 3 ? slab_thickness : 1.0);
    const double Vg = dim == 2 ? M_PI * d * d / 4 : M_PI * d * d * d / 6;
    dem::check_memory((1 - (dim == 3 ? porosity_3d : porosity)) * Vr / Vg, dim,
                      memory_limit, w,
                      "DEM region/grain diameter (or the material file's sizes)",
                      "DEM region/memory limit");
    if (dim == 3)
      {
        // Random dense packings of spheres: about 0.36 in bulk, looser next
        // to walls; outside [0.3, 0.6] grain scaling either jams with large
        // overlaps or leaves a loose cloud.
        dem::check_range(w, "DEM region/porosity (3D)", porosity_3d, 0.3, 0.6);
        dem::check_range(w, "DEM region/fj_Nal", fj_Nal, 3, 64);
        // At least two of the largest grains through the slab, so that the
        // slab is a granular layer and not a monolayer between the walls.
        dem::check_range(w, "DEM region/slab thickness", slab_thickness, 2 * d_hi,
                         4 * radius);
      }
  }

  namespace
  {
    // Portable random numbers, no <random> distributions (docs/architecture.md,
    // "Random numbers").
    double uniform(std::mt19937_64 &g)
    {
      return (g() >> 11) * (1.0 / 9007199254740992.0);
    }

    template <int dim>
    void set_radius(dem::Particles<dim> &P, std::size_t i, double r, double density)
    {
      P.radius[i] = r;
      if constexpr (dim == 2)
        {
          P.mass[i]    = density * M_PI * r * r;
          P.inertia[i] = 0.5 * P.mass[i] * r * r;
        }
      else
        {
          P.mass[i]    = density * dem::ball_volume<3>(r);
          P.inertia[i] = 0.4 * P.mass[i] * r * r;
        }
    }

    // Cycles until the ratio-average is below `ratio` (checked every 100
    // steps) or `limit` steps; returns whether it settled.
    template <int dim>
    bool settle(dem::Model<dim> &m, double ratio, std::int64_t limit)
    {
      for (std::int64_t n = 0; n < limit; n += 100)
        {
          m.cycle(100);
          const double r = m.unbalanced_ratio();
          if (r < ratio)
            return true;
          if (!std::isfinite(r)) // diverged: more steps cannot help
            return false;
        }
      return false;
    }

    // Distance from the origin to the segment [a, b] (2D points).
    double segment_distance(const Eigen::Vector2d &a, const Eigen::Vector2d &b)
    {
      const Eigen::Vector2d d  = b - a;
      const double          dd = d.squaredNorm();
      const double          t  = dd > 0 ? std::clamp(-a.dot(d) / dd, 0.0, 1.0) : 0.0;
      return (a + t * d).norm();
    }

    // 3D: radius of the largest cylinder about z inside the lateral facets
    // (their edges projected on the xy plane: chords, or points for
    // vertical edges); checks that the facets span 0 <= z <= t.
    double inscribed_radius_3d(const dem::Walls<3> &W, double b, double t)
    {
      double inner = b, zlo = HUGE_VAL, zhi = -HUGE_VAL;
      for (const auto &f : W.facet)
        for (int a = 0; a < 3; ++a)
          {
            const Vec<3> &p = W.vertex[f[a]], &q = W.vertex[f[(a + 1) % 3]];
            inner = std::min(inner, segment_distance(p.head<2>(), q.head<2>()));
            zlo   = std::min(zlo, p[2]);
            zhi   = std::max(zhi, p[2]);
          }
      const double tol = 1e-9 * std::max(b, t);
      if (std::abs(zlo) > tol || std::abs(zhi - t) > tol)
        throw dem::InputError(
            "DEM region: the lateral wall facets span z = " + std::to_string(zlo) +
            " .. " + std::to_string(zhi) + " m, not the slab 0 .. " + std::to_string(t) +
            " m (DEM region/slab thickness)");
      return inner;
    }

    template <int dim>
    double porosity(const dem::Particles<dim> &P, double volume)
    {
      double v = 0;
      for (double r : P.radius)
        v += dem::ball_volume<dim>(r);
      return 1 - v / volume;
    }
  } // namespace

  int add_cylinder_ring(dem::Walls<3> &W, double radius, double thickness,
                        unsigned int n_around, unsigned int n_layers,
                        const std::string &name)
  {
    if (n_around < 3 || n_layers < 1 || !(radius > 0) || !(thickness > 0))
      throw dem::InputError("add_cylinder_ring: needs radius > 0, thickness > 0, at "
                            "least 3 facets around and 1 layer");
    const int        wall = W.add_wall(name);
    std::vector<int> v((n_layers + 1) * n_around);
    for (unsigned int l = 0; l <= n_layers; ++l)
      for (unsigned int k = 0; k < n_around; ++k)
        {
          const double th     = 2 * M_PI * k / n_around;
          v[l * n_around + k] = W.add_vertex(Vec<3>(
              radius * std::cos(th), radius * std::sin(th), thickness * l / n_layers));
        }
    for (unsigned int l = 0; l < n_layers; ++l)
      for (unsigned int k = 0; k < n_around; ++k)
        {
          const unsigned int k1 = (k + 1) % n_around;
          const int          a = v[l * n_around + k], b = v[l * n_around + k1],
                    c = v[(l + 1) * n_around + k1], d = v[(l + 1) * n_around + k];
          W.add_facet(wall, {{a, b, c}});
          W.add_facet(wall, {{a, c, d}});
        }
    return wall;
  }

  // The carving leaves the rim's grains 1e-7 of their gap off the ring
  // (coupling/region_genesis.cc): the ring contacts close under the first
  // load, so the critical time step counts them from the start
  // (Model::touching_gap). Set for every region, where it is built.
  namespace
  {
    template <int dim>
    void count_touching_contacts(dem::Model<dim> &m)
    {
      m.touching_gap = 1e-6 * m.particles.min_radius();
    }
  } // namespace

  template <int dim>
  RegionGroups build_region(dem::Model<dim> &m, const RegionParams &p,
                            std::ostream *progress)
  {
    p.validate("DEM region", dim);
    using LN       = dem::LinearLaw<dim>;
    using FJ       = dem::FlatJointLaw<dim>;
    auto        &P = m.particles;
    auto        &W = m.walls;
    const double t = dim == 3 ? p.slab_thickness : 1.0; // 2D: unit thickness
    if (W.n_facets() < 8)
      throw std::runtime_error(
          "build_disk_region: the model needs the ring of wall facets");
    // Largest circle inside the ring polygon (chords lie inside the circle).
    double inner = p.radius;
    if constexpr (dim == 2)
      for (const auto &f : W.facet)
        inner = std::min(inner, 0.5 * (W.vertex[f[0]] + W.vertex[f[1]]).norm());
    else
      inner = inscribed_radius_3d(W, p.radius, t);
    const double volume = M_PI * inner * inner * t;

    RegionGroups G;
    if constexpr (dim == 3)
      {
        // The slab walls: one triangle per plane, containing the ring's
        // cross-section (x + y <= 2 e holds on the disk of radius e / 1.05).
        // One facet, not two: the engine gives a grain near an edge shared by
        // two coplanar facets a second contact on the edge, with a tilted
        // normal (an in-plane force on a frictionless wall).
        double reach = 0;
        for (const auto &x : W.vertex)
          reach = std::max(reach, 1.05 * x.template head<2>().norm());
        for (int s = 0; s < 2; ++s)
          {
            const double z  = s * t;
            const int    w  = W.add_wall(s == 0 ? "slab wall z=0" : "slab wall z=t");
            const int    v0 = W.add_vertex(Vec<3>(-2 * reach, -2 * reach, z)),
                      v1    = W.add_vertex(Vec<3>(4 * reach, -2 * reach, z)),
                      v2    = W.add_vertex(Vec<3>(-2 * reach, 4 * reach, z));
            W.add_facet(w, {{v0, v1, v2}});
            G.slab_walls[s] = w;
          }
      }
    if (p.material)
      {
        RegionGroups carved = carve_region<dim>(m, p, inner, G, progress);
        count_touching_contacts(m);
        return carved;
      }
    // Gap of contact k of a group at the current positions. The groups'
    // gaps are those of the latest force pass, one position update old; 3D
    // recomputes them so that the smoothing and the bonding see the packing
    // as it is (2D keeps the stored ones: its results stay as they were).
    auto gap = [&](const dem::ContactGroupBase<dim> &grp, std::size_t k) {
      if constexpr (dim == 2)
        return grp.gap[k];
      else
        {
          const auto i = grp.end1[k], j = grp.end2[k];
          if (!grp.is_wall[k])
            return (P.x[j] - P.x[i]).norm() - P.radius[i] - P.radius[j];
          std::array<double, dim> w;
          return (W.closest_point(j, P.x[i], w) - P.x[i]).norm() - P.radius[i];
        }
    };
    auto is_slab_facet = [&](std::size_t k) {
      return dim == 3 &&
             (W.facet_wall[k] == G.slab_walls[0] || W.facet_wall[k] == G.slab_walls[1]);
    };

    // Grain count for the target porosity (fistPkg §4.2.1: N from the
    // solid area (volume) and the mean grain area (volume) of the size
    // distribution).
    std::mt19937_64     gen(p.seed);
    std::vector<double> radii;
    const double        solid =
        dim == 2 ? (1 - p.porosity) * M_PI * inner * inner : (1 - p.porosity_3d) * volume;
    for (double a = 0; a < solid;)
      {
        const double d = p.d_lo + (p.d_hi - p.d_lo) * uniform(gen);
        radii.push_back(0.5 * d);
        a += dim == 2 ? M_PI * 0.25 * d * d : M_PI / 6 * d * d * d;
      }
    // Random cloud at half size (grain scaling from a loose cloud).
    const double s0 = 0.5;
    for (double r : radii)
      {
        const double rho = std::sqrt(uniform(gen)) * (inner - r),
                     th  = 2 * M_PI * uniform(gen);
        Vec<dim> x;
        x[0] = rho * std::cos(th);
        x[1] = rho * std::sin(th);
        if constexpr (dim == 3)
          x[2] = r + (t - 2 * r) * uniform(gen);
        P.add(x, s0 * r, p.density, 0);
      }

    const double rmean = 0.25 * (p.d_lo + p.d_hi);
    // Packing groups: one frictionless stiffness for every contact, that of
    // a contact between two grains of the mean final radius (memo Eq. 40).
    // The radii grow after the contacts are made, so a per-contact value set
    // at installation would go stale; the packing is a numerical device and
    // its contacts do not outlive it. The material's groups below are per
    // contact.
    {
      dem::ContactGeometry<dim> gbb, gbw;
      gbb.R1 = gbb.R2 = gbw.R1 = rmean;
      gbw.ball_wall            = true;
      const dem::Deformability pack{p.lnm_emod, 0};
      typename LN::Params      q;
      q.kn        = pack.kn_force(gbb);
      G.pack      = m.template add_law<LN>(q, "DEM region (packing)");
      q.kn        = pack.kn_force(gbw);
      G.pack_wall = m.template add_law<LN>(q, "DEM region (packing, ring)");
    }
    m.set_default_law(G.pack, G.pack_wall);
    m.local_damping = 0.7;
    m.set_timestep(0);
    m.skin = 0.2 * rmean;

    // Grow to full size in 20 increments, relaxing in between.
    const int n_grow = 20;
    for (int k = 1; k <= n_grow; ++k)
      {
        const double s = s0 + (1 - s0) * k / n_grow;
        for (std::size_t i = 0; i < P.size(); ++i)
          set_radius(P, i, s * radii[i], p.density);
        m.reset_energy_baseline();
        m.invalidate_contacts();
        m.cycle(200);
      }
    if (!settle(m, 1e-3, 200000))
      {
        // A non-finite ratio is a packing that blew up (e.g. a modulus so
        // large that the forces overflow), not a slow one: say so.
        const double ratio = m.unbalanced_ratio();
        throw std::runtime_error(
            std::isfinite(ratio)
                ? "DEM region: packing did not reach equilibrium (unbalanced-force "
                  "ratio " +
                      std::to_string(ratio) + " after 200000 steps, limit 1e-3)"
                : std::string("DEM region: the packing diverged (non-finite forces): "
                              "the contact moduli (DEM region/emod, lnm emod, or the "
                              "material file's) are out of any physical range"));
      }
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
      }
    if (progress)
      *progress << "DEM region: " << P.size() << " grains packed in " << m.step_count()
                << " steps\n";

    // The grain pairs to bond: those touching at the end of packing (within
    // the installation gap). 2D takes them after the smoothing below from
    // the stored gaps, which are still those of the packing; 3D from the
    // packing's geometry here. Overlaps: how tight the packing is.
    struct Pair
    {
      std::uint32_t i, j;
    };
    std::vector<Pair> pairs;
    m.detect_contacts();
    {
      double      sum = 0, mx = 0;
      std::size_t n = 0;
      for (int g : {G.pack, G.pack_wall})
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (!grp.is_wall[k])
              {
                const double gk = gap(grp, k);
                if (dim == 3 && gk <= p.igap)
                  pairs.push_back({grp.end1[k], grp.end2[k]});
                if (gk < 0)
                  {
                    sum += -gk;
                    mx = std::max(mx, -gk);
                    ++n;
                  }
              }
        }
      G.max_overlap_ratio  = mx / rmean;
      G.mean_overlap_ratio = n > 0 ? sum / n / rmean : 0.0;
    }

    // Grain-wall smoothing: shrink each touching grain by its overlap so no
    // grain-wall contact carries force (finalization, fistPkg §4.2.2). Its
    // bonds to the neighbours stay (installed force-free across the small
    // gap the shrinking opens).
    if constexpr (dim == 2)
      for (int g : {G.pack, G.pack_wall})
        {
          auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (grp.is_wall[k] && grp.gap[k] < 0)
              {
                const auto i = grp.end1[k];
                set_radius(P, i, P.radius[i] + grp.gap[k] * 1.0000001, p.density);
              }
        }
    else
      {
        // By the largest overlap of the grain over its wall contacts: a grain
        // in a corner (ring and slab wall) or on the diagonal of a slab wall
        // has several, and shrinking by each in turn would shrink it more
        // than needed.
        std::vector<double> worst(P.size(), 0.0);
        for (int g : {G.pack, G.pack_wall})
          {
            const auto &grp = m.group(g);
            for (std::size_t k = 0; k < grp.size(); ++k)
              if (grp.is_wall[k])
                worst[grp.end1[k]] = std::min(worst[grp.end1[k]], gap(grp, k));
          }
        for (std::size_t i = 0; i < P.size(); ++i)
          if (worst[i] < 0)
            set_radius(P, i, P.radius[i] + worst[i] * 1.0000001, p.density);
      }
    m.invalidate_contacts();
    m.detect_contacts();
    G.packed_porosity = porosity(P, volume);

    // Laws of the finished material.
    G.linear = m.template add_law<LN>(
        {}, "DEM region (linear)",
        dem::linear_rule<dim>({p.lnm_emod, p.lnm_krat}, p.lnm_fric));
    G.wall = m.template add_law<LN>({}, "DEM region (ring)",
                                    dem::linear_rule<dim>({p.emod, p.krat}, p.wall_fric));
    if constexpr (dim == 3) // plane strain: frictionless, as a symmetry plane
      G.slab_wall = m.template add_law<LN>({}, "DEM region (slab walls)",
                                           dem::linear_rule<dim>({p.emod, 0}, 0));

    // Bonding: one flat-joint group, each joint's block by the rule.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> walls_touching;
    for (int g : {G.pack, G.pack_wall})
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k] && dim == 2 && gap(grp, k) <= p.igap)
            pairs.push_back({grp.end1[k], grp.end2[k]});
          else if (grp.is_wall[k] && gap(grp, k) <= p.igap)
            walls_touching.emplace_back(grp.end1[k], grp.end2[k]);
      }
    {
      const double        huge = 1e30; // unbreakable bonds (verification)
      typename FJ::Params q;
      q.Nr     = p.fj_Nr;
      q.Nal    = p.fj_Nal; // 3D only
      q.fric   = p.fric;
      q.fa     = p.fj_fa;
      q.bonded = true;
      const dem::Distribution ten{p.breakable ? p.fj_ten : huge, 0};
      const dem::Distribution coh{p.breakable ? p.fj_coh : huge, 0};
      G.bond =
          m.template add_law<FJ>(q, "DEM region (flat joints)",
                                 dem::flat_joint_rule<dim>({p.emod, p.krat}, ten, coh,
                                                           dem::StrengthDraws(p.seed)));
    }
    for (const auto &pr : pairs)
      m.install(pr.i, pr.j, G.bond);
    G.n_bonds = pairs.size();
    for (const auto &[i, f] : walls_touching)
      m.install_wall(i, f, is_slab_facet(f) ? G.slab_wall : G.wall);
    // Remaining packing contacts (not touching) move to the material's
    // linear laws, as do new contacts.
    for (int g : {G.pack, G.pack_wall})
      while (m.group(g).size() > 0)
        {
          const std::size_t k    = m.group(g).size() - 1;
          const auto       &grp  = m.group(g);
          const int         dest = !grp.is_wall[k]              ? G.linear
                                   : is_slab_facet(grp.end2[k]) ? G.slab_wall
                                                                : G.wall;
          m.reassign(dem::ContactRef{g, k}, dest);
        }
    // Rattlers (grains without a bond, left loose by the frictionless
    // packing) are removed: they carry no stress and would drift into the
    // excavation, spoiling the wall convergence.
    {
      std::vector<char> bonded(P.size(), 0);
      for (const auto &pr : pairs)
        bonded[pr.i] = bonded[pr.j] = 1;
      std::vector<char> rm(P.size(), 0);
      std::size_t       n_rm = 0;
      for (std::size_t i = 0; i < P.size(); ++i)
        n_rm += (rm[i] = !bonded[i]);
      if (n_rm > 0)
        m.remove_particles(rm);
      G.n_rattlers = n_rm;
    }
    m.set_default_law(G.linear, G.wall);
    if constexpr (dim == 3)
      {
        // New contacts with the slab walls stay frictionless, whatever
        // default wall law a coupling variant sets later.
        std::vector<char> slab(W.n_facets(), 0);
        for (std::size_t k = 0; k < W.n_facets(); ++k)
          slab[k] = is_slab_facet(k);
        const int law          = G.slab_wall;
        m.new_wall_contact_law = [slab, law](std::uint32_t, std::uint32_t k) {
          return k < slab.size() && slab[k] ? law : -1;
        };
      }
    m.local_damping = p.damping;
    m.invalidate_contacts();
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
        P.x0[i] = P.x[i];
      }
    m.reset_energy_baseline();
    G.porosity = porosity(P, volume);
    // Inside the rim (two of the largest grains off the ring), where the
    // looser layer along the ring does not reach (dem_region.h).
    const double r_interior = inner - 2 * p.d_hi;
    G.interior_porosity =
        r_interior > 0.3 * inner ? dem::column_porosity(m, r_interior, t) : G.porosity;
    if (progress)
      {
        *progress << "DEM region: " << G.n_bonds << " flat joints, "
                  << walls_touching.size() << " grains on the ring, " << G.n_rattlers
                  << " rattlers removed\n";
        if constexpr (dim == 3)
          *progress << "DEM region: slab 0 < z < " << t << " m, porosity "
                    << G.packed_porosity << " packed (target " << p.porosity_3d << "), "
                    << G.porosity << " without rattlers; grain overlap / mean radius "
                    << G.mean_overlap_ratio << " mean, " << G.max_overlap_ratio
                    << " max\n";
      }
    count_touching_contacts(m);
    return G;
  }

  template RegionGroups build_region<2>(dem::Model<2> &, const RegionParams &,
                                        std::ostream *);
  template RegionGroups build_region<3>(dem::Model<3> &, const RegionParams &,
                                        std::ostream *);

  Eigen::Matrix2d region_stress(const dem::Model<2> &m, const Vec<2> &c, double r)
  {
    Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k] && (grp.xc[k] - c).norm() < r)
            {
              const Vec<2> l = m.particles.x[grp.end2[k]] - m.particles.x[grp.end1[k]];
              s -= grp.force[k] * l.transpose();
            }
      }
    s /= M_PI * r * r;
    return 0.5 * (s + s.transpose());
  }

  namespace
  {
    // Love-Weber sum over the contacts whose contact point lies in the
    // cylinder |(x - c)_xy| < r, z0 <= z <= z1, divided by `volume`.
    Eigen::Matrix3d love_weber_3d(const dem::Model<3> &m, const Vec<3> &c, double r,
                                  double z0, double z1, double volume)
    {
      // sigma = (1/V) sum over the grains p of sum over their contacts of
      // (x_c - x_p) f_p^T (f_p the force on p; tension positive). A
      // grain-grain contact (force[k] on end 2, -force[k] on end 1) gives
      // -force[k] (x2 - x1)^T; a grain-wall contact (force[k] on the wall)
      // gives -force[k] (x_c - x1)^T, x_c the contact location (within half
      // the overlap of the wall surface). Transposes do not matter: the
      // result is symmetrized.
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if ((grp.xc[k] - c).head<2>().norm() < r && grp.xc[k][2] >= z0 &&
                grp.xc[k][2] <= z1)
              {
                const Vec<3> l =
                    grp.is_wall[k]
                        ? Vec<3>(grp.xc[k] - m.particles.x[grp.end1[k]])
                        : Vec<3>(m.particles.x[grp.end2[k]] - m.particles.x[grp.end1[k]]);
                s -= grp.force[k] * l.transpose();
              }
        }
      s /= volume;
      return 0.5 * (s + s.transpose());
    }
  } // namespace

  Eigen::Matrix3d region_stress(const dem::Model<3> &m, const Vec<3> &c, double r,
                                double thickness)
  {
    return love_weber_3d(m, c, r, -HUGE_VAL, HUGE_VAL, M_PI * r * r * thickness);
  }

  Eigen::Matrix3d region_stress(const dem::Model<3> &m, const Vec<3> &c, double r,
                                double z0, double z1)
  {
    return love_weber_3d(m, c, r, z0, z1, M_PI * r * r * (z1 - z0));
  }
} // namespace demfem::coupling
