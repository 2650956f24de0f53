// Finalization phase of material genesis (fistPkg §4.2.2): bonded contacts
// at grain pairs with gap <= g_i, flat-jointed microstructure (§2.6.2),
// remaining contacts linear, reference surfaces without force, grain-vessel
// smoothing.
#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/property_rules.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <tuple>

namespace demfem::dem
{
  template <int dim>
  void finalize_specimen(Specimen<dim> &s, Random &rng, std::ostream *progress,
                         bool smooth_vessel, const std::vector<double> &shrunk)
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
    // The material's linear group: deformability per contact (memo Eq. 40).
    s.linear_group =
        m.template add_law<LN>({}, where + " (linear group)",
                               linear_rule<dim>({p.lnm_emod, p.lnm_krat}, p.lnm_fric));
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
          if (!shrunk.empty() && shrunk.size() != N)
            throw std::invalid_argument("finalize_specimen: one shrinking per grain");
          // Beyond the installation gap, grain i reaches as far as the
          // caller's shrinking opened its packing contacts (shrunk[i] is the
          // radius it lost, margin included; 1e-6 relative covers the
          // round-off of the recomputed gap); the sweep's bound uses the
          // largest reach.
          auto reach = [&](std::uint32_t i) {
            return shrunk.empty() ? 0.0 : shrunk[i] * (1 + 1e-6);
          };
          const double reach_max =
              shrunk.empty()
                  ? 0.0
                  : *std::max_element(shrunk.begin(), shrunk.end()) * (1 + 1e-6);
          for (std::size_t a = 0; a < N; ++a)
            for (std::size_t b = a + 1; b < N; ++b)
              {
                const std::uint32_t i = o[a], j = o[b];
                if (P.x[j][0] - P.radius[j] >
                    P.x[i][0] + P.radius[i] + p.igap + reach(i) + reach_max)
                  break;
                if ((P.x[j] - P.x[i]).norm() - P.radius[i] - P.radius[j] <=
                    p.igap + reach(i) + reach(j))
                  pairs.emplace_back(std::min(i, j), std::max(i, j));
              }
          std::sort(pairs.begin(), pairs.end());
        }
        // One bonded group; each contact's block from the material's rule
        // (deformability, strength draws from their own stream).
        const StrengthDraws draws(rng.index(std::uint64_t(1) << 62));
        const Deformability bonded{p.emod, p.krat};
        if (p.type == "flatjointed")
          {
            s.bond_group = m.template add_law<FJ>(
                flat_joint_params<dim>(p), where + " (flat joints)",
                flat_joint_rule<dim>(bonded, p.fj_ten, p.fj_coh, draws));
          }
        else if (p.type == "parallelbonded")
          {
            typename PB::Params q;
            q.pb_rmul    = p.pb_rmul;
            q.pb_mcf     = p.pb_mcf;
            q.pb_fa      = p.pb_fa;
            q.bonded     = true;
            s.bond_group = m.template add_law<PB>(
                q, where + " (parallel bonds)",
                parallel_bond_rule<dim>(bonded, p.fric, {p.pb_bemod, p.pb_bkrat},
                                        p.pb_ten, p.pb_coh, draws));
          }
        else
          {
            typename CB::Params q;
            q.bonded     = true;
            s.bond_group = m.template add_law<CB>(
                q, where + " (contact bonds)",
                contact_bond_rule<dim>(bonded, p.fric, p.cb_tens, p.cb_shears, draws));
          }
        JointList joints;
        joints.group = s.bond_group;
        for (const auto &[i, j] : pairs)
          {
            joints.index.push_back(m.install(i, j, s.bond_group).index);
            joints.i.push_back(i);
            joints.j.push_back(j);
          }
        if (p.type == "flatjointed" && !pairs.empty())
          {
            std::tie(s.fj_rmul_min, s.fj_rmul_max) =
                set_radius_multipliers(m, joints, p.fj_rmul_code, p.fj_rmul);
            designate_microstructure(m, joints, p.fj_B, p.fj_G, p.fj_gap, rng);
          }
      }

    // Grain-vessel smoothing (§4.2.2): move each wall outward by the largest
    // grain overlap on it, so no grain-wall contact carries force.
    std::array<double, dim> delta;
    delta.fill(0);
    const auto &V = s.vessel;
    for (int g = 0; g < (smooth_vessel ? m.n_groups() : 0); ++g)
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
    if (p.is_bonded() && smooth_vessel)
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

  template void finalize_specimen(Specimen<2> &, Random &, std::ostream *, bool,
                                  const std::vector<double> &);
  template void finalize_specimen(Specimen<3> &, Random &, std::ostream *, bool,
                                  const std::vector<double> &);
} // namespace demfem::dem
