#include "coupling/dem_region.h"

#include "dem/flat_joint_law.h"
#include "dem/linear_law.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace demfem::coupling
{
  using dem::Vec;

  void RegionParams::validate(const std::string &w) const
  {
    const double inf = HUGE_VAL;
    dem::check_range(w, "DEM region/radius", radius, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (smallest)", d_lo, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (largest)", d_hi, d_lo, inf);
    dem::check_range(w, "DEM region/density", density, 0, inf, true);
    dem::check_range(w, "DEM region/porosity", porosity, 0.05, 0.5);
    dem::check_range(w, "DEM region/local damping", damping, 0, 1, false, true);
    dem::check_range(w, "DEM region/lnm_emod", lnm_emod, 0, inf, true);
    dem::check_range(w, "DEM region/lnm_krat", lnm_krat, 0, inf, true);
    dem::check_range(w, "DEM region/lnm_fric", lnm_fric, 0, inf);
    dem::check_range(w, "DEM region/emod", emod, 0, inf, true);
    dem::check_range(w, "DEM region/krat", krat, 0, inf, true);
    dem::check_range(w, "DEM region/fric", fric, 0, inf);
    dem::check_range(w, "DEM region/igap", igap, 0, inf);
    dem::check_range(w, "DEM region/fj_Nr", fj_Nr, 1, 64);
    dem::check_range(w, "DEM region/fj_ten", fj_ten, 0, inf);
    dem::check_range(w, "DEM region/fj_coh", fj_coh, 0, inf);
    dem::check_range(w, "DEM region/fj_fa", fj_fa, 0, 90, false, true);
    if (d_hi > 0.25 * radius)
      throw dem::InputError(w + ": DEM region/grain diameter " + std::to_string(d_hi) +
                            " m is too large for the region radius " +
                            std::to_string(radius) + " m (allowed: <= radius/4)");
  }

  namespace
  {
    // DESIGN §8: portable random numbers (no <random> distributions).
    double uniform(std::mt19937_64 &g)
    {
      return (g() >> 11) * (1.0 / 9007199254740992.0);
    }

    void set_radius(dem::Particles<2> &P, std::size_t i, double r, double density)
    {
      P.radius[i]  = r;
      P.mass[i]    = density * M_PI * r * r;
      P.inertia[i] = 0.5 * P.mass[i] * r * r;
    }

    // Cycles until the ratio-average is below `ratio` (checked every 100
    // steps) or `limit` steps; returns whether it settled.
    bool settle(dem::Model<2> &m, double ratio, std::int64_t limit)
    {
      for (std::int64_t n = 0; n < limit; n += 100)
        {
          m.cycle(100);
          if (m.unbalanced_ratio() < ratio)
            return true;
        }
      return false;
    }
  } // namespace

  RegionGroups build_disk_region(dem::Model<2> &m, const RegionParams &p,
                                 std::ostream *progress)
  {
    p.validate("DEM region");
    using LN = dem::LinearLaw<2>;
    using FJ = dem::FlatJointLaw<2>;
    auto &P  = m.particles;
    auto &W  = m.walls;
    if (W.n_facets() < 8)
      throw std::runtime_error(
          "build_disk_region: the model needs the ring of wall facets");
    // Largest circle inside the ring polygon (chords lie inside the circle).
    double inner = p.radius;
    for (const auto &f : W.facet)
      inner = std::min(inner, 0.5 * (W.vertex[f[0]] + W.vertex[f[1]]).norm());

    // Grain count for the target porosity (fistPkg §4.2.1: N from the
    // solid area and the mean grain area of the size distribution).
    std::mt19937_64     gen(p.seed);
    std::vector<double> radii;
    const double        solid = (1 - p.porosity) * M_PI * inner * inner;
    for (double a = 0; a < solid;)
      {
        const double d = p.d_lo + (p.d_hi - p.d_lo) * uniform(gen);
        radii.push_back(0.5 * d);
        a += M_PI * 0.25 * d * d;
      }
    // Random cloud at half size (grain scaling from a loose cloud).
    const double s0 = 0.5;
    for (double r : radii)
      {
        const double rho = std::sqrt(uniform(gen)) * (inner - r),
                     th  = 2 * M_PI * uniform(gen);
        P.add(Vec<2>(rho * std::cos(th), rho * std::sin(th)), s0 * r, p.density, 0);
      }

    RegionGroups G;
    const double rmean = 0.25 * (p.d_lo + p.d_hi);
    LN::Params   pk;
    pk.kn       = p.lnm_emod; // 2 r E*/(2 r): deformability of equal grains
    pk.ks       = 0;
    pk.friction = 0;
    G.pack      = m.add_law<LN>(pk, "DEM region (packing)");
    pk.kn       = 2 * p.lnm_emod; // grain-wall: L = R (memo Eq. 40)
    G.pack_wall = m.add_law<LN>(pk, "DEM region (packing, ring)");
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
      throw std::runtime_error("DEM region: packing did not reach equilibrium (ratio " +
                               std::to_string(m.unbalanced_ratio()) + ")");
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
      }
    if (progress)
      *progress << "DEM region: " << P.size() << " grains packed in " << m.step_count()
                << " steps\n";

    // Grain-ring smoothing: shrink each touching grain by its overlap so no
    // grain-ring contact carries force (finalization, fistPkg §4.2.2).
    m.detect_contacts();
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
    m.invalidate_contacts();
    m.detect_contacts();

    // Laws of the finished material.
    LN::Params ln;
    ln.kn       = p.lnm_emod;
    ln.ks       = p.lnm_emod / p.lnm_krat;
    ln.friction = p.lnm_fric;
    G.linear    = m.add_law<LN>(ln, "DEM region (linear)");
    LN::Params lw;
    lw.kn       = 2 * p.emod;
    lw.ks       = lw.kn / p.krat;
    lw.friction = p.wall_fric;
    G.wall      = m.add_law<LN>(lw, "DEM region (ring)");

    // Bonding: flat joints binned by L = R1 + R2 within 1 % (as genesis).
    std::map<long long, int> bins;
    struct Pair
    {
      std::uint32_t i, j;
    };
    std::vector<Pair>                                    pairs;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> walls_touching;
    for (int g : {G.pack, G.pack_wall})
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k] && grp.gap[k] <= p.igap)
            pairs.push_back({grp.end1[k], grp.end2[k]});
          else if (grp.is_wall[k] && grp.gap[k] <= p.igap)
            walls_touching.emplace_back(grp.end1[k], grp.end2[k]);
      }
    const double huge = 1e30; // unbreakable bonds (verification)
    for (const auto &pr : pairs)
      {
        const double    L  = P.radius[pr.i] + P.radius[pr.j];
        const long long b  = std::llround(std::log(L) / std::log(1.01));
        auto            it = bins.find(b);
        if (it == bins.end())
          {
            FJ::Params q;
            q.Nr     = p.fj_Nr;
            q.rmul   = 1;
            q.gap0   = 0;
            q.kn     = p.emod / std::exp(b * std::log(1.01)); // memo Eq. 40
            q.ks     = q.kn / p.krat;
            q.fric   = p.fric;
            q.ten    = p.breakable ? p.fj_ten : huge;
            q.coh    = p.breakable ? p.fj_coh : huge;
            q.fa     = p.fj_fa;
            q.bonded = true;
            it = bins.emplace(b, m.add_law<FJ>(q, "DEM region (flat joints)")).first;
            G.bonds.push_back(it->second);
          }
        m.install(pr.i, pr.j, it->second);
      }
    G.n_bonds = pairs.size();
    for (const auto &[i, f] : walls_touching)
      m.install_wall(i, f, G.wall);
    // Remaining packing contacts (not touching) move to the material's
    // linear laws, as do new contacts.
    for (int g : {G.pack, G.pack_wall})
      while (m.group(g).size() > 0)
        {
          const std::size_t k = m.group(g).size() - 1;
          m.reassign(dem::ContactRef{g, k}, m.group(g).is_wall[k] ? G.wall : G.linear);
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
    m.local_damping = p.damping;
    m.invalidate_contacts();
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
        P.x0[i] = P.x[i];
      }
    m.reset_energy_baseline();
    if (progress)
      *progress << "DEM region: " << G.n_bonds << " flat joints in " << G.bonds.size()
                << " groups, " << walls_touching.size() << " grains on the ring, "
                << G.n_rattlers << " rattlers removed\n";
    return G;
  }

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
} // namespace demfem::coupling
