// Finalization phase of material genesis (fistPkg §4.2.2): bonded contacts
// at grain pairs with gap <= g_i, flat-jointed microstructure (§2.6.2),
// remaining contacts linear, reference surfaces without force, grain-vessel
// smoothing.
#include "dem/contact_bond_law.h"
#include "dem/flat_joint_law.h"
#include "dem/genesis.h"
#include "dem/linear_law.h"
#include "dem/parallel_bond_law.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace demfem::dem
{
  namespace
  {
    /// Quantization of per-contact values onto law groups. A group's Params
    /// are immutable, so contacts share a group when their deformability
    /// length L = R1 + R2 agrees within 1 % (kn error <= 0.5 %) and their
    /// strength draws agree to sd/4 (adds variance (sd/4)^2/12 < 0.6 % sd^2).
    long long lbin(double L) { return std::llround(std::log(L) / std::log(1.01)); }
    double    lval(long long b) { return std::exp(b * std::log(1.01)); }
    long long qbin(double x, const Distribution &d)
    {
      return d.sd > 0 ? std::llround(x / (0.25 * d.sd)) : 0;
    }
    double qval(long long b, const Distribution &d)
    {
      return d.sd > 0 ? b * 0.25 * d.sd : d.mean;
    }

    template <int dim>
    struct Face
    {
      std::size_t fj;  // index into the flat-joint list
      Vec<dim>    dir; // unit vector from the grain centre towards the face
      double      a;   // distance from the grain centre to the contact plane
      double      m;   // min(R1, R2): face radius = multiplier * m
    };

    /// Half-angle of the cone (3D) or wedge (2D) joining a face to its grain
    /// centre; two faces of one grain overlap iff their half-angles add up to
    /// more than the angle between their directions (fistPkg §2.6.2).
    double half_angle(double R, double a) { return std::atan2(R, a); }
  } // namespace

  template <int dim>
  void finalize_specimen(Specimen<dim> &s, Random &rng, std::ostream *progress)
  {
    using FJ                    = FlatJointLaw<dim>;
    using PB                    = ParallelBondLaw<dim>;
    using CB                    = ContactBondLaw<dim>;
    using LN                    = LinearLaw<dim>;
    auto                 &m     = s.model;
    auto                 &P     = m.particles;
    const MaterialParams &p     = s.material;
    const std::string     where = "material finalization";
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
      }
    double rbar = 0;
    for (double r : P.radius)
      rbar += r;
    rbar /= P.size();
    ContactGeometry<dim> gbb;
    gbb.R1 = gbb.R2 = rbar;
    s.linear_group =
        m.template add_law<LN>(LN::deformability(p.lnm_emod, p.lnm_krat, p.lnm_fric, gbb),
                               where + " (linear group)");
    // Every packing contact becomes a contact of the material's linear group.
    for (int g = 0; g < s.linear_group; ++g)
      if (g != s.wall_group)
        {
          auto                                                &grp = m.group(g);
          std::vector<std::pair<std::uint32_t, std::uint32_t>> c;
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (!grp.is_wall[k])
              c.emplace_back(grp.end1[k], grp.end2[k]);
          for (auto &[i, j] : c)
            m.install(i, j, s.linear_group);
        }
    m.set_default_law(s.linear_group, s.wall_group);

    if (p.is_bonded())
      {
        // Pairs with gap <= g_i (the CLEAN with proximity g_i of §4.2.2).
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
        {
          const std::size_t          N = P.size();
          std::vector<std::uint32_t> o(N);
          for (std::size_t i = 0; i < N; ++i)
            o[i] = static_cast<std::uint32_t>(i);
          std::sort(o.begin(), o.end(), [&](auto a, auto b) {
            const double xa = P.x[a][0] - P.radius[a], xb = P.x[b][0] - P.radius[b];
            return xa < xb || (xa == xb && a < b);
          });
          for (std::size_t a = 0; a < N; ++a)
            for (std::size_t b = a + 1; b < N; ++b)
              {
                const std::uint32_t i = o[a], j = o[b];
                if (P.x[j][0] - P.radius[j] > P.x[i][0] + P.radius[i] + p.igap)
                  break;
                if ((P.x[j] - P.x[i]).norm() - P.radius[i] - P.radius[j] <= p.igap)
                  pairs.emplace_back(std::min(i, j), std::max(i, j));
              }
          std::sort(pairs.begin(), pairs.end());
        }
        // Per-pair properties -> group key; members per key (ordered map:
        // deterministic group numbering).
        std::map<std::vector<long long>, std::vector<std::size_t>> members;
        std::vector<double>                                        gaps(pairs.size());
        for (std::size_t c = 0; c < pairs.size(); ++c)
          {
            const auto [i, j] = pairs[c];
            const double r1 = P.radius[i], r2 = P.radius[j];
            gaps[c] = (P.x[j] - P.x[i]).norm() - r1 - r2;
            std::vector<long long> key{lbin(r1 + r2)};
            if (p.type == "flatjointed")
              {
                key.push_back(qbin(rng.positive_normal(p.fj_ten), p.fj_ten));
                key.push_back(qbin(rng.positive_normal(p.fj_coh), p.fj_coh));
              }
            else
              {
                key.push_back(std::llround(std::log(std::min(r1, r2)) / std::log(1.01)));
                if (p.type == "parallelbonded")
                  {
                    key.push_back(qbin(rng.positive_normal(p.pb_ten), p.pb_ten));
                    key.push_back(qbin(rng.positive_normal(p.pb_coh), p.pb_coh));
                    // Reference gap = min gap of the group's members (<= 0):
                    // keep members within 1e-4 rbar of each other.
                    key.push_back(gaps[c] < 0
                                      ? std::llround(std::floor(gaps[c] / (1e-4 * rbar)))
                                      : 0);
                  }
                else
                  {
                    key.push_back(qbin(rng.positive_normal(p.cb_tens), p.cb_tens));
                    key.push_back(qbin(rng.positive_normal(p.cb_shears), p.cb_shears));
                    // The bonded contact bond carries kn (g - g_r) in both
                    // directions: only the exact gap gives no force.
                    long long bits;
                    std::memcpy(&bits, &gaps[c], sizeof bits);
                    key.push_back(bits);
                  }
              }
            members[key].push_back(c);
          }
        struct Joint
        {
          int           group;
          std::size_t   index;
          std::uint32_t i, j;
        };
        std::vector<Joint> joints;
        for (const auto &[key, list] : members)
          {
            const double L = lval(key[0]);
            int          g = -1;
            if (p.type == "flatjointed")
              {
                typename FJ::Params q;
                q.Nr     = p.fj_Nr;
                q.Nal    = p.fj_Nal;
                q.rmul   = p.fj_rmul;
                q.gap0   = 0;
                q.kn     = p.emod / L; // memo Eq. 40
                q.ks     = p.krat > 0 ? q.kn / p.krat : 0;
                q.fric   = p.fric;
                q.ten    = qval(key[1], p.fj_ten);
                q.coh    = qval(key[2], p.fj_coh);
                q.fa     = p.fj_fa;
                q.bonded = true;
                g        = m.template add_law<FJ>(q, where + " (flat-joint group)");
              }
            else
              {
                const double         rmin = std::exp(key[1] * std::log(1.01));
                ContactGeometry<dim> geo;
                geo.R1      = rmin;
                geo.R2      = std::max(L - rmin, rmin);
                auto   lin  = LN::deformability(p.emod, p.krat, p.fric, geo);
                double gmin = 0;
                for (auto c : list)
                  gmin = std::min(gmin, gaps[c]);
                if (p.type == "parallelbonded")
                  {
                    typename PB::Params q;
                    q.linear               = lin;
                    q.linear.reference_gap = gmin;
                    q.pb_kn                = p.pb_bemod / L;
                    q.pb_ks                = p.pb_bkrat > 0 ? q.pb_kn / p.pb_bkrat : 0;
                    q.pb_rmul              = p.pb_rmul;
                    q.pb_mcf               = p.pb_mcf;
                    q.pb_ten               = qval(key[2], p.pb_ten);
                    q.pb_coh               = qval(key[3], p.pb_coh);
                    q.pb_fa                = p.pb_fa;
                    q.bonded               = true;
                    g = m.template add_law<PB>(q, where + " (parallel-bond group)");
                  }
                else
                  {
                    // Strengths are stresses (Table 3) on the cross section
                    // of the deformability method (2 R_min or pi R_min^2).
                    const double        A = dim == 2 ? 2 * rmin : M_PI * rmin * rmin;
                    typename CB::Params q;
                    q.linear               = lin;
                    q.linear.reference_gap = gaps[list.front()];
                    q.cb_tenf              = A * qval(key[2], p.cb_tens);
                    q.cb_shearf            = A * qval(key[3], p.cb_shears);
                    q.bonded               = true;
                    g = m.template add_law<CB>(q, where + " (contact-bond group)");
                  }
              }
            s.bond_groups.push_back(g);
            for (auto c : list)
              {
                const auto r = m.install(pairs[c].first, pairs[c].second, g);
                joints.push_back({r.group, r.index, pairs[c].first, pairs[c].second});
              }
          }
        s.bond_group = s.bond_groups.empty() ? -1 : s.bond_groups.front();

        if (p.type == "flatjointed" && !joints.empty())
          {
            // Radius multipliers (§2.6.2): code 0 fixed; 1/2 reduced
            // (non-uniformly / uniformly) until no two faces of a grain overlap.
            std::vector<double>                 mult(joints.size(), p.fj_rmul);
            std::vector<std::vector<Face<dim>>> faces(P.size());
            for (std::size_t f = 0; f < joints.size(); ++f)
              {
                const auto    &grp = m.group(joints[f].group);
                const auto     geo = grp.geometry(joints[f].index, P, m.walls);
                const auto     i = joints[f].i, j = joints[f].j;
                const double   mr      = std::min(P.radius[i], P.radius[j]);
                const Vec<dim> n       = geo.n; // from end1 towards end2
                const bool     i_first = grp.end1[joints[f].index] == i;
                const Vec<dim> n_i     = i_first ? n : Vec<dim>(-n);
                faces[i].push_back({f, n_i, (geo.xc - P.x[i]).dot(n_i), mr});
                faces[j].push_back({f, Vec<dim>(-n_i), (P.x[j] - geo.xc).dot(n_i), mr});
              }
            auto overlap = [&](const Face<dim> &a, const Face<dim> &b, double sa,
                               double sb) {
              const double th = std::acos(std::clamp(a.dir.dot(b.dir), -1.0, 1.0));
              return half_angle(sa * mult[a.fj] * a.m, a.a) +
                     half_angle(sb * mult[b.fj] * b.m, b.a) - th;
            };
            if (p.fj_rmul_code == 2)
              {
                auto valid = [&](double lam) {
                  for (const auto &fs : faces)
                    for (std::size_t a = 0; a < fs.size(); ++a)
                      for (std::size_t b = a + 1; b < fs.size(); ++b)
                        if (overlap(fs[a], fs[b], lam, lam) > 0)
                          return false;
                  return true;
                };
                double lo = 0, hi = 1;
                if (!valid(1))
                  {
                    for (int it = 0; it < 60; ++it)
                      ((valid(0.5 * (lo + hi))) ? lo : hi) = 0.5 * (lo + hi);
                    for (auto &x : mult)
                      x *= lo;
                  }
              }
            else if (p.fj_rmul_code == 1)
              for (const auto &fs : faces)
                for (std::size_t a = 0; a < fs.size(); ++a)
                  for (std::size_t b = a + 1; b < fs.size(); ++b)
                    if (overlap(fs[a], fs[b], 1, 1) > 0)
                      {
                        double lo = 0, hi = 1;
                        for (int it = 0; it < 60; ++it)
                          {
                            const double mid = 0.5 * (lo + hi);
                            (overlap(fs[a], fs[b], mid, mid) > 0 ? hi : lo) = mid;
                          }
                        mult[fs[a].fj] *= lo;
                        mult[fs[b].fj] *= lo;
                      }
            s.fj_rmul_min = *std::min_element(mult.begin(), mult.end());
            s.fj_rmul_max = *std::max_element(mult.begin(), mult.end());
            for (std::size_t f = 0; f < joints.size(); ++f)
              if (mult[f] != p.fj_rmul)
                {
                  auto &grp =
                      static_cast<ContactGroup<dim, FJ> &>(m.group(joints[f].group));
                  typename FJ::Params q = grp.params;
                  q.rmul                = mult[f];
                  FJ::install(q, grp.geometry(joints[f].index, P, m.walls),
                              grp.state(joints[f].index));
                }
            // Microstructure (§2.6.2, Eq. 1): the first n_B joints of a
            // spatially random list are bonded, the next n_G gapped (g_o
            // drawn from the gap distribution), the rest slit.
            std::vector<std::size_t> order(joints.size());
            for (std::size_t f = 0; f < order.size(); ++f)
              order[f] = f;
            for (std::size_t f = order.size(); f-- > 1;)
              std::swap(order[f], order[rng.index(f + 1)]);
            const auto n  = joints.size();
            const auto nB = static_cast<std::size_t>(std::llround(p.fj_B * n));
            const auto nG =
                std::min(n - nB, static_cast<std::size_t>(std::llround(p.fj_G * n)));
            for (std::size_t r = nB; r < n; ++r)
              {
                const auto &J   = joints[order[r]];
                auto       &grp = static_cast<ContactGroup<dim, FJ> &>(m.group(J.group));
                double     *st  = grp.state(J.index);
                if (r < nB + nG)
                  FJ::set_initial_gap(grp.params, st, rng.positive_normal(p.fj_gap));
                else
                  FJ::unbond(grp.params, st);
              }
          }
      }

    // Grain-vessel smoothing (§4.2.2): move each wall outward by the largest
    // grain overlap on it, so no grain-wall contact carries force.
    std::array<double, dim> delta;
    delta.fill(0);
    const auto &V = s.vessel;
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (grp.is_wall[k])
            {
              // Current gap (the stored one is from before the last move).
              const double gap = grp.geometry(k, P, m.walls).gap;
              const int    w   = m.walls.facet_wall[grp.end2[k]];
              for (int a = 0; a < dim; ++a)
                if (gap < 0 && (w == V.lo[a] || w == V.hi[a] || (a == 0 && w == V.side)))
                  delta[a] = std::max(delta[a], -gap);
            }
      }
    if (p.is_bonded())
      {
        for (int a = 0; a < dim; ++a)
          if (delta[a] > 0 && (V.lo[a] >= 0 || (a == 0 && V.side >= 0)))
            V.translate_outward(m.walls, a, delta[a] * (1 + 1e-9));
        s.vessel.reset_strain_reference(m.walls);
      }
    // Zero the stored forces and take one step: the bonded material starts
    // from rest and free of force.
    for (std::size_t i = 0; i < P.size(); ++i)
      P.x0[i] = P.x[i];
    m.invalidate_contacts();
    m.reset_energy_baseline();
    m.step();
    if (progress)
      {
        const auto c = contact_counts(m);
        *progress << "genesis: finalized " << p.type << ": grains " << c.grains
                  << ", coordination " << c.coordination << ", bonds " << c.bonds
                  << ", flat joints " << c.fj << " (B " << c.fj_bonded << ", G "
                  << c.fj_gapped << ", S " << c.fj_slit << ")\n";
      }
  }

  template void finalize_specimen(Specimen<2> &, Random &, std::ostream *);
  template void finalize_specimen(Specimen<3> &, Random &, std::ostream *);
} // namespace demfem::dem
